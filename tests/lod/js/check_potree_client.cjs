// Loads a Potree 2.0 directory with a real Potree client, @pnext/three-loader (the loader of
// Potree 2.0 data for three.js), and compares every node with what Parallax's reader gives.
//
//   node check_potree_client.cjs DIR EXPECTED.json
//
// EXPECTED.json is `potree_test_tool dump DIR` (tests/lod/potree_test_tool.cpp). Exit status 0
// when every node matches, 1 on any difference or failure (never a skip).
//
// How the library runs here, in plain Node rather than a browser: its own code does all the
// work. DIR is served over HTTP on 127.0.0.1 with Range requests (as a static web server
// serves Potree data), the library fetches metadata.json, hierarchy chunks (proxies included)
// and node byte ranges of octree.bin with fetch(), parses the hierarchy itself, and decodes
// nodes in its own decoder worker: the worker's source, which the library ships inline as a
// Blob URL, runs in a worker_threads thread behind a small Web Worker shim. Only three browser
// globals are stubbed: `self`, `document` (its WebGL feature probe finds no canvas) and
// `Worker`.
//
// What is compared, per node (the library decodes positions to float32 relative to the node's
// box, colours from 16 to 8 bits as value / 256 when above 255, and keeps every other
// attribute's exact values in `preciseBuffer`):
//   - the set of node names and each node's point count;
//   - positions: |client - parallax| <= |client float| * 2^-23 + 1e-9 * |world|;
//   - colours: within 1 (the client truncates value / 256, Parallax rounds value / 257), in
//     every node whenever metadata.json declares rgb (both readers must then give colours);
//   - every other attribute: exactly (the first element of arrays, as the client reads them);
//     Potree names map to Parallax's by ' ' and '-' -> '_', NormalX/Y/Z and a 3-element
//     normal / normals / NORMAL to the normals (as float32), and a
//     uint8 declared field read by Parallax as int8 (scan angle rank) compares modulo 256.
// It prints one line per node with its point count and checksums of positions and colours.
'use strict';

const fs = require('fs');
const http = require('http');
const path = require('path');
const { Worker: ThreadWorker } = require('worker_threads');
const { resolveObjectURL } = require('buffer');

const [, , dir, expectedFile] = process.argv;
if (!dir || !expectedFile) {
  console.error('usage: node check_potree_client.cjs DIR EXPECTED.json');
  process.exit(1);
}

// ---- browser globals the library touches -------------------------------------------------
globalThis.self = globalThis;
globalThis.document = { createElement: () => ({ getContext: () => null }) };

const workerErrors = [];
const threads = [];
// A Web Worker over a worker_threads thread: the library creates it from a Blob URL holding
// the decoder's source and talks to it with postMessage / onmessage.
class WebWorkerShim {
  constructor(url) {
    const blob = resolveObjectURL(url);
    if (!blob) throw new Error(`worker shim: ${url} is not a Blob URL`);
    this.onmessage = null;
    this.ready = blob.text().then((code) => {
      const prelude =
        "const { parentPort } = require('worker_threads');" +
        'globalThis.self = globalThis; globalThis.onmessage = null;' +
        'globalThis.postMessage = (message, transfer) => parentPort.postMessage(message, transfer);' +
        "parentPort.on('message', (data) => globalThis.onmessage({ data }));\n";
      const thread = new ThreadWorker(prelude + code, { eval: true });
      thread.on('message', (data) => this.onmessage && this.onmessage({ data }));
      thread.on('error', (error) => workerErrors.push(error));
      threads.push(thread);
      return thread;
    });
  }
  postMessage(message, transfer) {
    this.ready.then((thread) => thread.postMessage(message, transfer));
  }
  terminate() {
    this.ready.then((thread) => thread.terminate());
  }
}
globalThis.Worker = WebWorkerShim;

const { V2_LOADER } = require('@pnext/three-loader');

// ---- a static file server with Range requests --------------------------------------------
const requests = new Map();  // file name -> requests served
function serve(root) {
  const server = http.createServer((request, response) => {
    const name = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    requests.set(name, (requests.get(name) || 0) + 1);
    const file = path.join(root, name);
    if (!file.startsWith(root) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      response.writeHead(404).end();
      return;
    }
    const size = fs.statSync(file).size;
    const range = /^bytes=(\d+)-(\d+)$/.exec(request.headers.range || '');
    if (range) {
      const first = Number(range[1]);
      const last = Math.min(Number(range[2]), size - 1);
      if (first > last) {
        response.writeHead(416, { 'Content-Range': `bytes */${size}` }).end();
        return;
      }
      response.writeHead(206, {
        'Content-Range': `bytes ${first}-${last}/${size}`,
        'Content-Length': last - first + 1,
      });
      fs.createReadStream(file, { start: first, end: last }).pipe(response);
      return;
    }
    response.writeHead(200, { 'Content-Length': size });
    fs.createReadStream(file).pipe(response);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// Loads one node through the library (its hierarchy chunk first when it is a proxy).
async function loadNode(node) {
  while (node.loading) await sleep(2);
  if (!node.loaded) await node.load();
  while (node.loading) await sleep(2);
  if (workerErrors.length) throw workerErrors[0];
  if (!node.loaded) throw new Error(`three-loader could not load node ${node.name}`);
}

function checksum(values) {
  let sum = 0;
  values.forEach((v, i) => (sum += v * ((i % 7) + 1)));
  return sum;
}

async function main() {
  const expected = JSON.parse(fs.readFileSync(expectedFile, 'utf8'));
  const expectedNodes = new Map(expected.nodes.map((n) => [n.name, n]));
  const metadata = JSON.parse(fs.readFileSync(path.join(dir, 'metadata.json'), 'utf8'));
  const declaresColour = metadata.attributes.some((a) => a.name === 'rgb' || a.name === 'rgba');
  const server = await serve(path.resolve(dir));
  const base = `http://127.0.0.1:${server.address().port}`;
  const failures = [];
  const fail = (message) => {
    failures.push(message);
    if (failures.length <= 20) console.error(`MISMATCH ${message}`);
  };

  const geometry = await V2_LOADER(
    `${base}/metadata.json`,
    (url) => url,
    (url, init) => fetch(url, init),
  );
  const queue = [geometry.root];
  const seen = new Set();
  let points = 0;
  while (queue.length) {
    const node = queue.shift();
    await loadNode(node);
    seen.add(node.name);
    for (const child of node.children) if (child) queue.push(child);

    const want = expectedNodes.get(node.name);
    if (!want) {
      fail(`node ${node.name}: three-loader has it, Parallax does not`);
      continue;
    }
    if (node.numPoints !== want.points) {
      fail(`node ${node.name}: ${node.numPoints} points in three-loader, ${want.points} in Parallax`);
      continue;
    }
    points += node.numPoints;
    const attributes = node.geometry.attributes;
    const positions = node.geometry.getAttribute('position').array;
    const min = geometry.offset.clone().add(node.boundingBox.min);
    const world = [];
    for (let i = 0; i < node.numPoints; i++) {
      for (let c = 0; c < 3; c++) {
        const f = positions[3 * i + c];
        const w = f + min.getComponent(c);
        const p = want.positions[i][c];
        world.push(w);
        if (!(Math.abs(w - p) <= Math.abs(f) * 2 ** -23 + 1e-9 * Math.abs(p))) {
          fail(`node ${node.name} point ${i} axis ${c}: three-loader ${w}, Parallax ${p}`);
        }
      }
    }
    // Whether colours are compared follows the metadata, never what either reader happened to
    // report: a reader that drops every colour must fail, not skip the comparison.
    let colorSum = 0;
    if (declaresColour && !want.colors) {
      fail(`node ${node.name}: metadata.json declares rgb, Parallax reports no colours`);
    }
    if (!declaresColour && want.colors) {
      fail(`node ${node.name}: metadata.json declares no rgb, Parallax reports colours`);
    }
    if (declaresColour && want.colors) {
      const rgba = attributes.rgba && attributes.rgba.array;
      if (!rgba) fail(`node ${node.name}: three-loader decoded no colours`);
      if (rgba && rgba.length < 4 * node.numPoints) {
        fail(`node ${node.name}: three-loader decoded ${rgba.length / 4} colours for ` +
             `${node.numPoints} points`);
      }
      for (let i = 0; rgba && i < node.numPoints; i++) {
        for (let c = 0; c < 3; c++) {
          colorSum += rgba[4 * i + c];
          if (Math.abs(rgba[4 * i + c] - want.colors[i][c]) > 1) {
            fail(`node ${node.name} point ${i} colour ${c}: three-loader ${rgba[4 * i + c]}, ` +
                 `Parallax ${want.colors[i][c]}`);
          }
        }
      }
    }
    for (const attribute of metadata.attributes) {
      const name = attribute.name;
      if (name === 'position' || name === 'rgb' || name === 'rgba') continue;
      const decoded = attributes[name];
      if (!decoded || !decoded.potree) {
        fail(`node ${node.name}: three-loader decoded no '${name}'`);
        continue;
      }
      const exact = decoded.potree.preciseBuffer;
      const normalAxis = { NormalX: 0, NormalY: 1, NormalZ: 2 }[name];
      let column = want.columns[name.replace(/[ -]/g, '_')];
      if (!column && attribute.numElements > 1) column = want.columns[`${name}[0]`];
      const vectorNormal = ['normal', 'normals', 'NORMAL'].includes(name) && want.normals;
      if ((normalAxis !== undefined && want.normals) || vectorNormal) {
        column = want.normals.map((n) => n[vectorNormal ? 0 : normalAxis]);
      }
      if (!column) {
        fail(`node ${node.name}: Parallax has no column for '${name}'`);
        continue;
      }
      const bits = 8 * attribute.elementSize;
      for (let i = 0; i < node.numPoints; i++) {
        let p = column[i];
        if (p < 0 && attribute.type.startsWith('uint')) p += 2 ** bits;  // uint8 read as int8
        const v = Number(exact[i]);
        const equal = normalAxis !== undefined || vectorNormal ? Math.fround(v) === Math.fround(p) : v === p;
        if (!equal) fail(`node ${node.name} point ${i} '${name}': three-loader ${v}, Parallax ${p}`);
      }
    }
    console.log(`node ${node.name.padEnd(8)} ${String(node.numPoints).padStart(8)} points` +
                `  positions ${checksum(world).toFixed(3)}  colours ${colorSum}`);
  }
  for (const name of expectedNodes.keys()) {
    if (!seen.has(name)) fail(`node ${name}: Parallax has it, three-loader does not`);
  }
  if (points !== expected.points) fail(`${points} points in three-loader, ${expected.points} in Parallax`);
  server.close();
  await Promise.all(threads.map((t) => t.terminate()));
  if (failures.length) {
    console.error(`FAILED: ${failures.length} difference(s) between three-loader and Parallax`);
    process.exit(1);
  }
  console.log(`OK: ${seen.size} nodes, ${points} points read alike by @pnext/three-loader and ` +
              `Parallax (${requests.get('/hierarchy.bin') || 0} hierarchy chunk(s) fetched)`);
  process.exit(0);
}

// A hang (a worker that never answers) is a failure, not a pass.
setTimeout(() => {
  console.error('FAILED: timed out after 120 s');
  process.exit(1);
}, 120000).unref();

main().catch((error) => {
  console.error(`FAILED: ${error && error.stack ? error.stack : error}`);
  process.exit(1);
});
