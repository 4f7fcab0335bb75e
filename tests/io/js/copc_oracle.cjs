// copc.js (npm `copc` 0.0.8, the COPC reader Potree's viewer uses; laz-perf decodes its chunks)
// as the oracle of Parallax's COPC files, in plain Node.
//
//   node copc_oracle.cjs check FILE.copc.laz REFERENCE.las
//       Walks FILE's hierarchy as copc.js does, following every child page; decodes every node's
//       chunk; checks that each point lies in its node's cube and that the points of every inner
//       node are at least that level's spacing apart (Poisson sampling's promise); that the CRS
//       (WKT) is the reference's; and that the
//       records of all nodes are exactly the point records of REFERENCE.las (an uncompressed LAS
//       file of the same point format and record length), each found exactly once.
//       Both modes also read FILE front to back as a plain LAZ reader does (laz-perf's LASZip,
//       through the LAZ chunk table: COPC's chunks are variable, one a node, each with its own
//       point count and size): the records must be the nodes' own, node after node in file order.
//   node copc_oracle.cjs summary FILE.copc.laz
//       The pages, nodes and points copc.js finds, each point in its node's cube (for files of
//       other writers, which sample otherwise: no spacing check).
// Prints one line and exits 0 on success, 1 on any difference or failure (never a skip).
'use strict';

const fs = require('fs');
const { Copc, Las } = require('copc');
const { createLazPerf } = require('laz-perf');

function fail(message) {
  console.error('FAILED: ' + message);
  process.exit(1);
}

// The point records of an uncompressed LAS file (LAS 1.4 R15 Table 3 offsets).
function lasRecords(file) {
  const b = fs.readFileSync(file);
  if (b.toString('latin1', 0, 4) !== 'LASF') fail(file + ' is not a LAS file');
  const offset = b.readUInt32LE(96);
  const format = b.readUInt8(104);
  const length = b.readUInt16LE(105);
  let count = b.readUInt32LE(107);
  if (b.readUInt8(25) >= 4) count = Number(b.readBigUInt64LE(247)) || count;
  if (format & 0xc0) fail(file + ' is compressed: the reference must be plain LAS');
  // The WKT of the CRS (LASF_Projection 2112 among the VLRs), or undefined.
  let wkt;
  let at = b.readUInt16LE(94);
  for (let i = 0; i < b.readUInt32LE(100); ++i) {
    const user = b.toString('latin1', at + 2, at + 18).replace(/\0.*$/, '');
    const id = b.readUInt16LE(at + 18), size = b.readUInt16LE(at + 20);
    if (user === 'LASF_Projection' && id === 2112) {
      wkt = b.toString('latin1', at + 54, at + 54 + size).replace(/\0.*$/, '');
    }
    at += 54 + size;
  }
  return { records: b.subarray(offset, offset + count * length), count, length, format, wkt };
}

// The LAZ chunk size of the laszip VLR (user "laszip encoded", record 22204: compressor, coder,
// version, revision, options, then the chunk size); 0xffffffff for variable chunks.
function lazChunkSize(file) {
  const b = fs.readFileSync(file);
  let at = b.readUInt16LE(94);
  for (let i = 0; i < b.readUInt32LE(100); ++i) {
    const user = b.toString('latin1', at + 2, at + 18).replace(/\0.*$/, '');
    const id = b.readUInt16LE(at + 18), size = b.readUInt16LE(at + 20);
    if (user === 'laszip encoded' && id === 22204) return b.readUInt32LE(at + 54 + 12);
    at += 54 + size;
  }
  fail(file + ' has no laszip VLR');
}

// Every record laz-perf's LASZip decodes reading FILE front to back, as one Buffer.
function frontToBack(file, lazPerf) {
  const bytes = fs.readFileSync(file);
  const input = lazPerf._malloc(bytes.length);
  lazPerf.HEAPU8.set(bytes, input);
  const laszip = new lazPerf.LASZip();
  try {
    laszip.open(input, bytes.length);
    const count = laszip.getCount(), length = laszip.getPointLength();
    const point = lazPerf._malloc(length);
    const out = Buffer.alloc(count * length);
    for (let i = 0; i < count; ++i) {
      laszip.getPoint(point);
      out.set(lazPerf.HEAPU8.subarray(point, point + length), i * length);
    }
    lazPerf._free(point);
    return out;
  } finally {
    laszip.delete();
    lazPerf._free(input);
  }
}

// Every node of the file, from every page (copc.js's own page parser).
async function walk(file) {
  const copc = await Copc.create(file);
  const nodes = {};
  let pages = 0;
  const queue = [copc.info.rootHierarchyPage];
  while (queue.length > 0) {
    const page = queue.shift();
    const { nodes: found, pages: children } = await Copc.loadHierarchyPage(file, page);
    ++pages;
    for (const [key, node] of Object.entries(found)) {
      if (nodes[key]) fail(`key ${key} is listed by two pages`);
      nodes[key] = node;
    }
    for (const child of Object.values(children)) queue.push(child);
  }
  return { copc, nodes, pages };
}

function cubeOf(info, key) {
  const [d, x, y, z] = key.split('-').map(Number);
  const size = (info.cube[3] - info.cube[0]) / 2 ** d;
  return {
    min: [info.cube[0] + x * size, info.cube[1] + y * size, info.cube[2] + z * size],
    size,
  };
}

// The smallest distance between two of `points` ([x, y, z] arrays) that is below `limit`, or
// Infinity: a grid of `limit`-sized cells, each point against its cell and the 26 around it.
function closestBelow(points, limit) {
  const grid = new Map();
  const cell = (v) => Math.floor(v / limit);
  let best = Infinity;
  for (const p of points) {
    const c = p.map(cell);
    for (let dx = -1; dx <= 1; ++dx) {
      for (let dy = -1; dy <= 1; ++dy) {
        for (let dz = -1; dz <= 1; ++dz) {
          const list = grid.get(`${c[0] + dx},${c[1] + dy},${c[2] + dz}`);
          if (!list) continue;
          for (const q of list) {
            const d = Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
            if (d < best) best = d;
          }
        }
      }
    }
    const k = `${c[0]},${c[1]},${c[2]}`;
    if (!grid.has(k)) grid.set(k, []);
    grid.get(k).push(p);
  }
  return best < limit ? best : Infinity;
}

async function check(file, reference) {
  const { copc, nodes, pages } = await walk(file);
  const { header, info } = copc;
  const lazPerf = await createLazPerf();
  const ref = reference ? lasRecords(reference) : null;
  if (ref && (ref.length !== header.pointDataRecordLength || ref.format !== header.pointDataRecordFormat)) {
    fail(`${file}: point format ${header.pointDataRecordFormat} (${header.pointDataRecordLength} bytes), ` +
         `the reference ${ref.format} (${ref.length} bytes)`);
  }
  if (ref && ref.wkt !== copc.wkt) {
    fail(`${file}: CRS ${JSON.stringify(copc.wkt)}, the reference's ${JSON.stringify(ref.wkt)}`);
  }
  const length = header.pointDataRecordLength;
  const seen = new Map();  // record (latin1 string) -> times
  let points = 0, inner = 0;
  const keys = Object.keys(nodes);
  const hasChildren = new Set();
  const chunks = [];  // each node's records and where its chunk starts
  for (const key of keys) {
    const [d, x, y, z] = key.split('-').map(Number);
    if (d > 0) hasChildren.add(`${d - 1}-${x >> 1}-${y >> 1}-${z >> 1}`);
  }
  for (const key of keys) {
    const node = nodes[key];
    if (node.pointCount === 0) continue;
    const buffer = await Copc.loadPointDataBuffer(file, header, node, lazPerf);
    const view = Las.View.create(buffer, header, copc.eb);
    if (view.pointCount !== node.pointCount || buffer.length !== node.pointCount * length) {
      fail(`node ${key}: ${view.pointCount} points decoded, the hierarchy says ${node.pointCount}`);
    }
    const gx = view.getter('X'), gy = view.getter('Y'), gz = view.getter('Z');
    const cube = cubeOf(info, key);
    const slack = 1e-6 * (info.cube[3] - info.cube[0]);
    const xyz = [];
    for (let i = 0; i < view.pointCount; ++i) {
      const p = [gx(i), gy(i), gz(i)];
      for (let a = 0; a < 3; ++a) {
        if (p[a] < cube.min[a] - slack || p[a] > cube.min[a] + cube.size + slack) {
          fail(`node ${key}: point ${i} (${p}) is outside its cube`);
        }
      }
      xyz.push(p);
      const record = Buffer.from(buffer.buffer, buffer.byteOffset + i * length, length).toString('latin1');
      seen.set(record, (seen.get(record) || 0) + 1);
    }
    points += view.pointCount;
    chunks.push({ offset: node.pointDataOffset, records: Buffer.from(buffer) });
    if (ref && hasChildren.has(key)) {
      ++inner;
      const spacing = info.spacing / 2 ** Number(key.split('-')[0]);
      // Positions are quantized: allow one quantization step of the three axes.
      const tolerance = Math.hypot(...header.scale);
      const closest = closestBelow(xyz, spacing - tolerance);
      if (closest !== Infinity) {
        fail(`node ${key}: two points ${closest} apart, below the level's spacing ${spacing}`);
      }
    }
  }
  if (points !== header.pointCount) fail(`${points} points in the nodes, the header says ${header.pointCount}`);
  let summary = `${file}: copc.js read ${pages} hierarchy pages, ${keys.length} nodes, ${points} points`;
  // The chunk table: variable chunks, read front to back, are the nodes in file order.
  if (lazChunkSize(file) !== 0xffffffff) fail(`${file}: fixed LAZ chunks, COPC's are variable`);
  chunks.sort((a, b) => a.offset - b.offset);
  const nodeOrder = Buffer.concat(chunks.map((c) => c.records));
  const plain = frontToBack(file, lazPerf);
  if (plain.length !== nodeOrder.length) {
    fail(`${file}: a plain LAZ read through the chunk table gives ${plain.length / length} points, ` +
         `the nodes ${nodeOrder.length / length}`);
  }
  for (let c = 0, at = 0; c < chunks.length; at += chunks[c].records.length, ++c) {
    if (!plain.subarray(at, at + chunks[c].records.length).equals(chunks[c].records)) {
      fail(`${file}: chunk ${c} (at byte ${chunks[c].offset}) read through the chunk table ` +
           `differs from its node's points`);
    }
  }
  const sizes = new Set(chunks.map((c) => c.records.length / length));
  summary += `; laz-perf read its ${chunks.length} variable chunks (${sizes.size} sizes) front to ` +
             'back through the chunk table, each its node\'s points';
  if (ref) summary += `; ${inner} inner nodes keep their level's spacing`;
  if (ref) {
    if (ref.count !== points) fail(`${points} points in ${file}, ${ref.count} in ${reference}`);
    for (let i = 0; i < ref.count; ++i) {
      const record = ref.records.subarray(i * length, (i + 1) * length).toString('latin1');
      const times = seen.get(record);
      if (!times) fail(`point ${i} of ${reference} is not in ${file} (or is there with other attributes)`);
      seen.set(record, times - 1);
    }
    for (const times of seen.values()) {
      if (times !== 0) fail(`a point of ${file} is there more often than in ${reference}`);
    }
    summary += `; every point of ${reference} found exactly once, with all its attributes`;
    if (ref.wkt) summary += '; the same WKT';
  }
  console.log(summary);
}

const [mode, file, reference] = process.argv.slice(2);
if (mode === 'check' && file && reference) {
  check(file, reference).catch((e) => fail(e.stack || String(e)));
} else if (mode === 'summary' && file) {
  check(file, null).catch((e) => fail(e.stack || String(e)));
} else {
  fail('usage: copc_oracle.cjs check FILE.copc.laz REFERENCE.las | summary FILE.copc.laz');
}
