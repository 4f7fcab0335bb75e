// The second LAZ decoder of the tests: laz-perf (its WebAssembly build, in plain Node).
//
//   node laz_oracle.cjs dump FILE.laz OUT.bin        every point record laz-perf decodes, back to
//                                                    back, into OUT.bin
//   node laz_oracle.cjs compare FILE.laz FILE.las [FILE.laz FILE.las ...]
//                                                    laz-perf's records of each FILE.laz against
//                                                    the point records stored in the FILE.las
//                                                    after it, byte for byte, pair by pair (one
//                                                    Node start and one laz-perf module for all)
// Prints one line a file (points, point format, record length; and the result) and exits 0 on
// success, 1 at the first difference or failure (never a skip).
'use strict';

const fs = require('fs');
const { createLazPerf } = require('laz-perf');

function fail(message) {
  console.error('FAILED: ' + message);
  process.exit(1);
}

// laz-perf's WebAssembly module, instantiated once for every file of a run.
let lazPerfModule = null;

// laz-perf's records of a LAZ file, as one Buffer, with its count, format and record length.
async function decode(file) {
  const bytes = fs.readFileSync(file);
  if (lazPerfModule === null) lazPerfModule = await createLazPerf();
  const lazPerf = lazPerfModule;
  const input = lazPerf._malloc(bytes.length);
  lazPerf.HEAPU8.set(bytes, input);
  const laszip = new lazPerf.LASZip();
  try {
    laszip.open(input, bytes.length);
    const count = laszip.getCount();
    const length = laszip.getPointLength();
    const format = laszip.getPointFormat();
    const point = lazPerf._malloc(length);
    const out = Buffer.alloc(count * length);
    for (let i = 0; i < count; ++i) {
      laszip.getPoint(point);
      out.set(lazPerf.HEAPU8.subarray(point, point + length), i * length);
    }
    lazPerf._free(point);
    return { records: out, count, length, format };
  } finally {
    laszip.delete();
    lazPerf._free(input);
  }
}

// The point records of an uncompressed LAS file (LAS 1.4 R15 Table 3 offsets).
function lasRecords(file) {
  const b = fs.readFileSync(file);
  if (b.toString('latin1', 0, 4) !== 'LASF') fail(file + ' is not a LAS file');
  const offset = b.readUInt32LE(96);
  const length = b.readUInt16LE(105);
  let count = b.readUInt32LE(107);
  if (b[25] >= 4 && count === 0) count = Number(b.readBigUInt64LE(247));
  return { records: b.subarray(offset, offset + count * length), count, length, format: b[104] & 63 };
}

async function compare(laz, las) {
  const got = await decode(laz);
  const summary = `${laz}: ${got.count} points, format ${got.format}, ${got.length} bytes a record`;
  const want = lasRecords(las);
  if (got.count !== want.count) fail(`${summary}: ${las} has ${want.count} points`);
  if (got.length !== want.length) fail(`${summary}: ${las} has ${want.length}-byte records`);
  if (got.format !== want.format) fail(`${summary}: ${las} has point format ${want.format}`);
  for (let i = 0; i < got.count; ++i) {
    const a = got.records.subarray(i * got.length, (i + 1) * got.length);
    const b = want.records.subarray(i * got.length, (i + 1) * got.length);
    if (!a.equals(b)) {
      fail(`${summary}: record ${i} differs from ${las}:\n  laz-perf ${a.toString('hex')}\n  las      ${b.toString('hex')}`);
    }
  }
  console.log(summary + ': every record equals ' + las);
}

async function main() {
  const [, , mode, ...files] = process.argv;
  const usage = 'usage: laz_oracle.cjs dump FILE.laz OUT.bin | compare FILE.laz FILE.las [FILE.laz FILE.las ...]';
  if (mode === 'dump') {
    if (files.length !== 2) fail(usage);
    const [laz, out] = files;
    const got = await decode(laz);
    fs.writeFileSync(out, got.records);
    console.log(`${laz}: ${got.count} points, format ${got.format}, ${got.length} bytes a record (laz-perf)`);
    return;
  }
  if (mode !== 'compare' || files.length === 0 || files.length % 2 !== 0) fail(usage);
  for (let i = 0; i < files.length; i += 2) await compare(files[i], files[i + 1]);
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
