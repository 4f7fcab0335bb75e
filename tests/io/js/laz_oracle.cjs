// The second LAZ decoder of the tests: laz-perf (its WebAssembly build, in plain Node).
//
//   node laz_oracle.cjs dump FILE.laz OUT.bin        every point record laz-perf decodes, back to
//                                                    back, into OUT.bin
//   node laz_oracle.cjs compare FILE.laz FILE.las    laz-perf's records of FILE.laz against the
//                                                    point records stored in FILE.las, byte for byte
// Prints one line (points, point format, record length; and the result) and exits 0 on success,
// 1 on any difference or failure (never a skip).
'use strict';

const fs = require('fs');
const { createLazPerf } = require('laz-perf');

function fail(message) {
  console.error('FAILED: ' + message);
  process.exit(1);
}

// laz-perf's records of a LAZ file, as one Buffer, with its count, format and record length.
async function decode(file) {
  const bytes = fs.readFileSync(file);
  const lazPerf = await createLazPerf();
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

async function main() {
  const [, , mode, laz, other] = process.argv;
  if (!mode || !laz || !other) fail('usage: laz_oracle.cjs dump FILE.laz OUT.bin | compare FILE.laz FILE.las');
  const got = await decode(laz);
  const summary = `${laz}: ${got.count} points, format ${got.format}, ${got.length} bytes a record`;
  if (mode === 'dump') {
    fs.writeFileSync(other, got.records);
    console.log(summary + ' (laz-perf)');
    return;
  }
  if (mode !== 'compare') fail('unknown mode ' + mode);
  const want = lasRecords(other);
  if (got.count !== want.count) fail(`${summary}: ${other} has ${want.count} points`);
  if (got.length !== want.length) fail(`${summary}: ${other} has ${want.length}-byte records`);
  if (got.format !== want.format) fail(`${summary}: ${other} has point format ${want.format}`);
  for (let i = 0; i < got.count; ++i) {
    const a = got.records.subarray(i * got.length, (i + 1) * got.length);
    const b = want.records.subarray(i * got.length, (i + 1) * got.length);
    if (!a.equals(b)) {
      fail(`${summary}: record ${i} differs from ${other}:\n  laz-perf ${a.toString('hex')}\n  las      ${b.toString('hex')}`);
    }
  }
  console.log(summary + ': every record equals ' + other);
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
