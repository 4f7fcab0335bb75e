// The layered chunk codec of LAZ (compressor 3, point formats 6-10): bit-exact agreement with
// LASzip both ways, exact round trips, and bad chunks refused with the first point affected.
//
// The expected values from LASzip come from tests/io/tools/laszip_expectations.cpp, run against
// LASzip 3.5.1 (github.com/LASzip/LASzip, built outside the repository) through its C API
// (laszip_api.h); its header says how to build it and how to compare its output with the tables
// here (or regenerate them):
//   - decoding: laszip_open_reader + laszip_read_point over the whole file, each laszip_point
//     written back as its raw LAS 1.4 record (the extended_* fields for the return, channel,
//     classification and scan angle bytes), then FNV-1a 64 over all records;
//   - encoding: the records of makeSyntheticRecords() written to an uncompressed LAS 1.4 file,
//     read by laszip_open_reader and written by laszip_open_writer after
//     laszip_request_native_extension(TRUE) and laszip_set_chunk_size(chunk) (item version 3;
//     for version 4 the header says LAS 1.5, which makes LASzip pick version 4), then FNV-1a 64
//     over the file's chunks (from the point data offset + 8 to the chunk table). The tool checks
//     that LASzip decodes each of those files back to exactly the input records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "io/laz/layered_codec.h"
#include "laz_synthetic_points.h"
#include "laz_test_file.h"
#include "support/test_data.h"

namespace parallax::laz {
namespace {

using testing::fnv1a64;
using testing::LazTestFile;
using testing::makeSyntheticRecords;
using testing::readLazTestFile;
using testing::SplitMix64;
using testing::syntheticRecordLength;
using testing::SyntheticSpec;

std::string hex(std::span<const std::byte> bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::byte b : bytes) {
    s += kDigits[std::uint8_t(b) >> 4];
    s += kDigits[std::uint8_t(b) & 15];
  }
  return s;
}

std::vector<std::byte> decodeFile(const LazTestFile& f) {
  auto decoder = makeLayeredDecoder(f.vlr.items);
  EXPECT_EQ(decoder->recordLength(), f.record_length);
  std::vector<std::byte> records(f.point_count * f.record_length);
  std::size_t at = 0;
  for (const auto& c : f.chunks) {
    decoder->decode(f.chunkBytes(c), c.points, records.data() + at);
    at += c.points * f.record_length;
  }
  return records;
}

// The items LASzip writes for a point format (item versions all `version`).
std::vector<LazItem> itemsFor(int format, std::size_t extra_bytes, std::uint16_t version) {
  std::vector<LazItem> items{{ItemType::Point14, 30, version}};
  if (format == 7) items.push_back({ItemType::Rgb14, 6, version});
  if (format == 8 || format == 10) items.push_back({ItemType::RgbNir14, 8, version});
  if (format == 9 || format == 10) items.push_back({ItemType::Wavepacket14, 29, version});
  if (extra_bytes != 0) items.push_back({ItemType::Byte14, std::uint16_t(extra_bytes), version});
  return items;
}

// Encodes `records` in chunks of `chunk` points; returns the chunks back to back.
std::vector<std::uint8_t> encodeChunks(ChunkEncoder& encoder, const std::vector<std::byte>& records,
                                       std::size_t chunk,
                                       std::vector<std::size_t>* sizes = nullptr) {
  const std::size_t length = encoder.recordLength();
  const std::size_t count = records.size() / length;
  std::vector<std::uint8_t> out;
  for (std::size_t at = 0; at < count; at += chunk) {
    const std::size_t before = out.size();
    encoder.encode(records.data() + at * length, std::min(chunk, count - at), out);
    if (sizes) sizes->push_back(out.size() - before);
  }
  return out;
}

// --- Real files: what LASzip decodes from them -------------------------------------------------

struct ExpectedRecord {
  std::size_t index;
  const char* hex;
};

void expectFileDecodesAsLaszip(const std::string& name, std::size_t points, std::size_t chunks,
                               std::uint64_t checksum, std::vector<ExpectedRecord> expected) {
  SCOPED_TRACE(name);
  const LazTestFile f = readLazTestFile(test::testDataFile(std::string("laz/") + name).string());
  ASSERT_EQ(f.point_count, points);
  ASSERT_EQ(f.chunks.size(), chunks);
  ASSERT_EQ(f.vlr.compressor, 3);
  const std::vector<std::byte> records = decodeFile(f);
  EXPECT_EQ(fnv1a64(records), checksum);
  for (const ExpectedRecord& e : expected) {
    EXPECT_EQ(hex(std::span(records).subspan(e.index * f.record_length, f.record_length)), e.hex)
        << "record " << e.index;
  }
}

TEST(LazLayered, DecodesSimpleCopcAsLaszip) {
  // 65 chunks of about 16 points: the per-chunk restart is exercised 65 times.
  expectFileDecodesAsLaszip(
      "simple.copc.laz", 1065, 65, 0x2b9c1be162ecbe35ull,
      {
          {0, "983cfeff5be0fcff4fe5ffff7c001140017c18fc9e1c14b1f7914cf40d4164005e007a00"},
          {1, "6112fefff921fdff52e3ffff93001100027c24fa9e1c591dff494ff40d41400046004a00"},
          {17, "ea14ffff419afcff3be4ffff64001100017c18fc9e1c013aaf9936f40d41b2008a00a200"},
          {532, "4510000024160300a8e3ffff74001140017cdc05a61c1182219d697d0e418a006b008800"},
          {1063, "1e42010082060300a1e3ffff3d001140017ab3fea51cfbf10d41b9710e4149005e005500"},
          {1064, "c28b01009e670200fde1ffff27001100027c71fba51cdd292c9ac5710e41a4008c009900"},
      });
}

TEST(LazLayered, DecodesEllipsoidCopcAsLaszip) {
  expectFileDecodesAsLaszip(
      "ellipsoid.copc.laz", 100000, 5, 0x53a386236f11ab8dull,
      {
          {0, "000000001027000000000000ff00218005000000070024d6e25300004540ff0000000000"},
          {1, "00000000f0d8ffff00000000800021800500000005008e588b4f010045400000ff00ff00"},
          {20000, "c331000030f8ffff8b090000800021000500bd1805008cd651d5042145400000d8007c00"},
          {31337, "f8dcffffdce0ffffa4010000ff00218005006cee040018601f9dba3a45409800cb00cb00"},
          {50001, "ae20000049e9ffff6ef4ffffff002200120047100100f5108dee20664540970097009400"},
          {99999, "c9020000c21300002defffff8000220011004d010300bbf2599e07774540db00db000000"},
      });
}

TEST(LazLayered, ReencodesCopcChunksToTheSameBytes) {
  // These files come from other writers; re-encoding their records gives their chunks back.
  for (const char* name : {"simple.copc.laz", "ellipsoid.copc.laz"}) {
    SCOPED_TRACE(name);
    const LazTestFile f = readLazTestFile(test::testDataFile(std::string("laz/") + name).string());
    const std::vector<std::byte> records = decodeFile(f);
    auto encoder = makeLayeredEncoder(f.vlr.items);
    std::size_t at = 0;
    for (const auto& c : f.chunks) {
      std::vector<std::uint8_t> out;
      encoder->encode(records.data() + at * f.record_length, c.points, out);
      at += c.points;
      const auto original = f.chunkBytes(c);
      ASSERT_EQ(out.size(), original.size());
      ASSERT_EQ(std::memcmp(out.data(), original.data(), out.size()), 0);
    }
  }
}

// --- The encoder writes LASzip's bytes ---------------------------------------------------------

struct LaszipOutput {
  SyntheticSpec spec;
  std::size_t chunk;
  std::uint16_t version;
  std::size_t bytes;       // of LASzip's chunks
  std::uint64_t checksum;  // FNV-1a 64 of LASzip's chunks
};

TEST(LazLayered, EncoderWritesLaszipBytes) {
  // Several scanner channels, multiple returns, GPS times that jump between sequences, quiet
  // chunks whose layers stay empty, and (last) chunks of two points, the last of one.
  const LaszipOutput cases[] = {
      {{.format = 6, .count = 12000, .seed = 2, .quiet_span = 3000},
       3000,
       3,
       108008,
       0x0b3b44474ce4f496ull},
      {{.format = 7, .count = 12000, .seed = 4, .quiet_span = 3000},
       3000,
       3,
       130327,
       0xf4d542768d1fbef2ull},
      {{.format = 7, .count = 12000, .seed = 4, .quiet_span = 3000},
       3000,
       4,
       132392,
       0x7ca79b75d59b31ffull},
      {{.format = 8, .extra_bytes = 5, .count = 12000, .seed = 6, .quiet_span = 2500},
       2500,
       3,
       132556,
       0x49a38451650db63aull},
      {{.format = 8, .extra_bytes = 5, .count = 12000, .seed = 6, .quiet_span = 2500},
       2500,
       4,
       137624,
       0x73623b5300c2bf28ull},
      {{.format = 9, .extra_bytes = 2, .count = 8000, .seed = 9, .quiet_span = 2000},
       2000,
       4,
       151966,
       0xbd06a786df965ebbull},
      {{.format = 10, .extra_bytes = 4, .count = 8000, .seed = 11, .quiet_span = 2000},
       2000,
       3,
       175840,
       0xee6e37fac5f8517bull},
      {{.format = 7, .extra_bytes = 1, .count = 5, .seed = 12}, 2, 3, 327, 0xa1e0da50f9d61ac4ull},
  };
  for (const LaszipOutput& c : cases) {
    SCOPED_TRACE("format " + std::to_string(c.spec.format) + ", version " +
                 std::to_string(c.version));
    const std::vector<std::byte> records = makeSyntheticRecords(c.spec);
    auto encoder = makeLayeredEncoder(itemsFor(c.spec.format, c.spec.extra_bytes, c.version));
    const std::vector<std::uint8_t> chunks = encodeChunks(*encoder, records, c.chunk);
    EXPECT_EQ(chunks.size(), c.bytes);
    EXPECT_EQ(fnv1a64(std::as_bytes(std::span(chunks))), c.checksum);
  }
}

// --- Round trips -------------------------------------------------------------------------------

void expectRoundTrip(const SyntheticSpec& spec, std::uint16_t version, std::size_t chunk) {
  SCOPED_TRACE("format " + std::to_string(spec.format) + ", " + std::to_string(spec.extra_bytes) +
               " extra bytes, version " + std::to_string(version) + ", chunks of " +
               std::to_string(chunk));
  const auto items = itemsFor(spec.format, spec.extra_bytes, version);
  const std::vector<std::byte> records = makeSyntheticRecords(spec);
  auto encoder = makeLayeredEncoder(items);
  auto decoder = makeLayeredDecoder(items);
  const std::size_t length = syntheticRecordLength(spec.format, spec.extra_bytes);
  ASSERT_EQ(encoder->recordLength(), length);
  ASSERT_EQ(decoder->recordLength(), length);
  std::vector<std::size_t> sizes;
  const std::vector<std::uint8_t> chunks = encodeChunks(*encoder, records, chunk, &sizes);
  std::vector<std::byte> decoded(records.size());
  std::size_t at = 0, point = 0;
  for (std::size_t size : sizes) {
    const std::size_t n = std::min(chunk, spec.count - point);
    decoder->decode(std::as_bytes(std::span(chunks)).subspan(at, size), n,
                    decoded.data() + point * length);
    at += size;
    point += n;
  }
  for (std::size_t i = 0; i < spec.count; ++i) {
    ASSERT_EQ(std::memcmp(decoded.data() + i * length, records.data() + i * length, length), 0)
        << "record " << i;
  }
}

TEST(LazLayered, RoundTripsEveryFormat) {
  for (int format = 6; format <= 10; ++format) {
    for (std::uint16_t version : {3, 4}) {
      for (std::size_t extra : {0, 1, 7}) {
        expectRoundTrip({.format = format,
                         .extra_bytes = extra,
                         .count = 2400,
                         .seed = std::uint64_t(100 + format * 10 + extra),
                         .quiet_span = 600},
                        version, 600);
      }
    }
  }
}

TEST(LazLayered, RoundTripsEdgeValues) {
  // Coordinates at the int32 limits, scan angles at the int16 limits, GPS times of -0.0, +0.0
  // and NaN (LASzip itself would turn -0.0 after +0.0 into +0.0).
  for (int format : {6, 8, 10}) {
    for (std::uint16_t version : {3, 4}) {
      expectRoundTrip({.format = format,
                       .extra_bytes = 3,
                       .count = 3000,
                       .seed = 77,
                       .quiet_span = 700,
                       .edge_values = true},
                      version, 700);
    }
  }
}

TEST(LazLayered, RoundTripsTinyAndOddChunks) {
  for (std::size_t chunk : {1, 2, 3, 17}) {
    expectRoundTrip({.format = 8, .extra_bytes = 2, .count = 40, .seed = 5}, 3, chunk);
  }
}

TEST(LazLayered, RoundTripsManyExtraBytes) {
  expectRoundTrip({.format = 7, .extra_bytes = 192, .count = 600, .seed = 8, .quiet_span = 200}, 4,
                  200);
}

// --- Layers and versions -----------------------------------------------------------------------

std::vector<std::uint32_t> layerSizes(std::span<const std::uint8_t> chunk, std::size_t length,
                                      std::size_t layers) {
  std::vector<std::uint32_t> sizes(layers);
  std::memcpy(sizes.data(), chunk.data() + length + 4, 4 * layers);
  return sizes;
}

TEST(LazLayered, UnchangedLayersAreEmpty) {
  // A chunk in which only the coordinates change: LASzip leaves every layer empty but the first
  // two (channel/returns/XY and Z, always written) and RGB.
  const SyntheticSpec spec{
      .format = 7, .extra_bytes = 2, .count = 2000, .seed = 3, .quiet_span = 1000};
  const std::vector<std::byte> records = makeSyntheticRecords(spec);
  auto encoder = makeLayeredEncoder(itemsFor(7, 2, 3));
  std::vector<std::uint8_t> quiet;
  // Points 1000..1999 form the quiet span.
  encoder->encode(records.data() + 1000 * 38, 1000, quiet);
  const auto sizes = layerSizes(quiet, 38, 12);
  EXPECT_GT(sizes[0], 0u);  // channel, returns, X, Y
  EXPECT_GT(sizes[1], 0u);  // Z
  for (std::size_t i = 2; i < 12; ++i) EXPECT_EQ(sizes[i], 0u) << "layer " << i;
  std::uint32_t count;
  std::memcpy(&count, quiet.data() + 38, 4);
  EXPECT_EQ(count, 1000u);

  // A busy chunk uses every layer but the first extra byte (constant in these records).
  std::vector<std::uint8_t> busy;
  encoder->encode(records.data(), 1000, busy);
  const auto busy_sizes = layerSizes(busy, 38, 12);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_GT(busy_sizes[i], 0u) << "layer " << i;
  EXPECT_EQ(busy_sizes[10], 0u);
  EXPECT_GT(busy_sizes[11], 0u);
}

TEST(LazLayered, OnePointChunk) {
  const SyntheticSpec spec{.format = 6, .count = 1, .seed = 4};
  const std::vector<std::byte> records = makeSyntheticRecords(spec);
  auto encoder = makeLayeredEncoder(itemsFor(6, 0, 3));
  std::vector<std::uint8_t> chunk;
  encoder->encode(records.data(), 1, chunk);
  // The raw point, the count, nine sizes, and the two layers LASzip always writes.
  const auto sizes = layerSizes(chunk, 30, 9);
  EXPECT_EQ(chunk.size(), 30 + 4 + 36 + sizes[0] + sizes[1]);
  EXPECT_EQ(std::memcmp(chunk.data(), records.data(), 30), 0);
  std::vector<std::byte> decoded(30);
  makeLayeredDecoder(itemsFor(6, 0, 3))->decode(std::as_bytes(std::span(chunk)), 1, decoded.data());
  EXPECT_EQ(decoded, records);
}

TEST(LazLayered, VersionsDifferOnlyWithSeveralChannels) {
  // Version 3 hands the items after POINT14 context 0 except where the channel changes; version
  // 4 the channel. With one channel (0) the two write the same bytes; with several they do not,
  // and each decodes only its own.
  SyntheticSpec spec{.format = 8, .extra_bytes = 3, .count = 3000, .seed = 16};
  std::vector<std::byte> records = makeSyntheticRecords(spec);
  const std::size_t length = syntheticRecordLength(8, 3);
  auto v3 = makeLayeredEncoder(itemsFor(8, 3, 3));
  auto v4 = makeLayeredEncoder(itemsFor(8, 3, 4));
  std::vector<std::uint8_t> a, b;
  v3->encode(records.data(), spec.count, a);
  v4->encode(records.data(), spec.count, b);
  EXPECT_NE(a, b);
  std::vector<std::byte> decoded(records.size());
  makeLayeredDecoder(itemsFor(8, 3, 4))
      ->decode(std::as_bytes(std::span(b)), spec.count, decoded.data());
  EXPECT_EQ(decoded, records);
  try {
    makeLayeredDecoder(itemsFor(8, 3, 4))
        ->decode(std::as_bytes(std::span(a)), spec.count, decoded.data());
    EXPECT_NE(decoded, records);
  } catch (const ChunkCorrupt&) {
    // also a right answer: the wrong contexts ran a layer past its end
  }

  for (std::size_t i = 0; i < spec.count; ++i) {
    records[i * length + 15] &= std::byte{0xCF};  // scanner channel 0 everywhere
  }
  a.clear();
  b.clear();
  v3->encode(records.data(), spec.count, a);
  v4->encode(records.data(), spec.count, b);
  EXPECT_EQ(a, b);
}

// --- Bad input ---------------------------------------------------------------------------------

struct EncodedChunk {
  std::vector<LazItem> items;
  std::vector<std::byte> records;
  std::vector<std::uint8_t> chunk;
  std::size_t count;
  std::size_t length;
};

EncodedChunk makeChunk(std::size_t count = 2000) {
  EncodedChunk c;
  c.items = itemsFor(7, 2, 3);
  c.count = count;
  c.length = syntheticRecordLength(7, 2);
  c.records = makeSyntheticRecords({.format = 7, .extra_bytes = 2, .count = count, .seed = 21});
  makeLayeredEncoder(c.items)->encode(c.records.data(), count, c.chunk);
  return c;
}

// Decodes, expecting ChunkCorrupt; returns its point (or SIZE_MAX when nothing was thrown). A
// decoder may be passed in: it must stay usable after a corrupt chunk.
std::size_t corruptPoint(const EncodedChunk& c, std::span<const std::uint8_t> chunk,
                         std::size_t count, std::vector<std::byte>& decoded,
                         std::string* what = nullptr, ChunkDecoder* decoder = nullptr) {
  std::unique_ptr<ChunkDecoder> own;
  if (!decoder) {
    own = makeLayeredDecoder(c.items);
    decoder = own.get();
  }
  decoded.assign(count * c.length, std::byte{0});
  try {
    decoder->decode(std::as_bytes(chunk), count, decoded.data());
  } catch (const ChunkCorrupt& e) {
    if (what) *what = e.what();
    return e.point();
  }
  return SIZE_MAX;
}

TEST(LazLayered, RefusesTruncatedChunks) {
  const EncodedChunk c = makeChunk();
  std::vector<std::byte> decoded;
  std::string what;
  // Inside the raw first point.
  EXPECT_EQ(corruptPoint(c, std::span(c.chunk).first(20), c.count, decoded, &what), 0u);
  EXPECT_NE(what.find("first point"), std::string::npos) << what;
  // Inside the table of layer sizes.
  EXPECT_EQ(corruptPoint(c, std::span(c.chunk).first(c.length + 10), c.count, decoded, &what), 1u);
  EXPECT_NE(what.find("table of layer sizes"), std::string::npos) << what;
  // Inside the layers: their sizes no longer add up.
  for (std::size_t cut : {c.chunk.size() - 1, c.chunk.size() / 2, c.length + 4 + 48 + 1}) {
    EXPECT_EQ(corruptPoint(c, std::span(c.chunk).first(cut), c.count, decoded, &what), 1u);
    EXPECT_NE(what.find("add up to"), std::string::npos) << what;
  }
  // Extra bytes after the layers.
  std::vector<std::uint8_t> longer = c.chunk;
  longer.push_back(0);
  EXPECT_EQ(corruptPoint(c, longer, c.count, decoded), 1u);
  // Bytes where no points were expected.
  EXPECT_EQ(corruptPoint(c, c.chunk, 0, decoded), 0u);
  EXPECT_EQ(corruptPoint(c, {}, 0, decoded), SIZE_MAX);
}

TEST(LazLayered, RefusesAWrongPointCount) {
  const EncodedChunk c = makeChunk();
  std::vector<std::byte> decoded;
  std::string what;
  // The chunk table expects more points than the chunk holds: the first missing one is affected.
  EXPECT_EQ(corruptPoint(c, c.chunk, c.count + 5, decoded, &what), c.count);
  EXPECT_NE(what.find("says it holds 2000 points, the chunk table 2005"), std::string::npos)
      << what;
  // The table expects fewer: the chunk and its table disagree, no coded point can be trusted.
  EXPECT_EQ(corruptPoint(c, c.chunk, c.count - 1, decoded), 1u);
  // A lying count in the chunk itself.
  std::vector<std::uint8_t> lying = c.chunk;
  const std::uint32_t huge = 0xFFFFFFFFu;
  std::memcpy(lying.data() + c.length, &huge, 4);
  EXPECT_EQ(corruptPoint(c, lying, c.count, decoded), 1u);
}

// Rebuilds the chunk with layer `layer` cut to its first `keep` bytes.
std::vector<std::uint8_t> cutLayer(const EncodedChunk& c, std::size_t layers, std::size_t layer,
                                   std::uint32_t keep) {
  std::vector<std::uint32_t> sizes = layerSizes(c.chunk, c.length, layers);
  const std::size_t header = c.length + 4 + 4 * layers;
  std::size_t start = header;
  for (std::size_t i = 0; i < layer; ++i) start += sizes[i];
  std::vector<std::uint8_t> out(c.chunk.begin(), c.chunk.begin() + std::ptrdiff_t(start + keep));
  out.insert(out.end(), c.chunk.begin() + std::ptrdiff_t(start + sizes[layer]), c.chunk.end());
  sizes[layer] = keep;
  std::memcpy(out.data() + c.length + 4, sizes.data(), 4 * layers);
  return out;
}

TEST(LazLayered, NamesTheFirstPointOfACutLayer) {
  // Cutting a layer short makes its stream run out at some point p: every point before p must
  // have decoded exactly (the records before the first point affected are valid), and the
  // shorter the layer, the earlier p.
  const EncodedChunk c = makeChunk(1000);
  const std::size_t layers = 9 + 1 + 2;  // POINT14, RGB14, two extra bytes
  std::vector<std::byte> decoded;
  for (std::size_t layer : {0u, 1u, 4u, 8u, 9u, 11u}) {
    const std::uint32_t size = layerSizes(c.chunk, c.length, layers)[layer];
    ASSERT_GT(size, 40u) << "layer " << layer;
    std::size_t previous = c.count;
    // (An empty layer is valid: it says the values never changed. Only the first layer must
    // always hold bytes.)
    std::vector<std::uint32_t> keeps = {size - 1, size - 7, size * 3 / 4, size / 2, size / 5, 3};
    if (layer == 0) keeps.push_back(0);
    for (std::uint32_t keep : keeps) {
      std::string what;
      const std::size_t p =
          corruptPoint(c, cutLayer(c, layers, layer, keep), c.count, decoded, &what);
      ASSERT_NE(p, SIZE_MAX) << "layer " << layer << " cut to " << keep;
      ASSERT_GE(p, 1u);
      ASSERT_LT(p, c.count);
      EXPECT_LE(p, previous) << "layer " << layer << " cut to " << keep;
      previous = p;
      EXPECT_EQ(std::memcmp(decoded.data(), c.records.data(), p * c.length), 0)
          << "layer " << layer << " cut to " << keep << ": records before point " << p;
      EXPECT_NE(what.find("runs past its end"), std::string::npos) << what;
    }
  }
}

TEST(LazLayered, SurvivesCorruptBytes) {
  // Flipped bytes inside the layers: the decoder either reports a corrupt chunk or decodes
  // something; it never crashes, hangs or reads outside the chunk (run under ASan in CI).
  const EncodedChunk c = makeChunk(500);
  SplitMix64 rng(99);
  std::vector<std::byte> decoded;
  auto decoder = makeLayeredDecoder(c.items);
  int refused = 0;
  for (int trial = 0; trial < 120; ++trial) {
    std::vector<std::uint8_t> bad = c.chunk;
    const std::size_t from = trial % 3 == 0 ? 0 : c.length + 4;  // sometimes the header too
    for (int k = 0; k < 1 + trial % 4; ++k) {
      bad[from + rng.below(std::uint32_t(bad.size() - from))] ^= std::uint8_t(1 + rng.below(255));
    }
    if (corruptPoint(c, bad, c.count, decoded, nullptr, decoder.get()) != SIZE_MAX) ++refused;
  }
  EXPECT_GT(refused, 0);
  // The same decoder still decodes a good chunk.
  EXPECT_EQ(corruptPoint(c, c.chunk, c.count, decoded, nullptr, decoder.get()), SIZE_MAX);
  EXPECT_EQ(decoded, c.records);
}

TEST(LazLayered, RefusesItemsItCannotCode) {
  const auto refuses = [](std::vector<LazItem> items, bool encoding = false) {
    try {
      if (encoding) {
        makeLayeredEncoder(items);
      } else {
        makeLayeredDecoder(items);
      }
    } catch (const UnsupportedItems& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refuses({}).find("empty"), std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point10, 20, 2}}).find("not an item of layered chunks"),
            std::string::npos);
  EXPECT_NE(refuses({{ItemType::Rgb14, 6, 3}}).find("the first"), std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 30, 3}, {ItemType::Point14, 30, 3}}).find("the first"),
            std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 20, 3}}).find("expected 30 bytes"), std::string::npos);
  EXPECT_NE(
      refuses({{ItemType::Point14, 30, 3}, {ItemType::RgbNir14, 6, 3}}).find("expected 8 bytes"),
      std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 30, 3}, {ItemType::Byte14, 0, 3}}).find("bytes"),
            std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 30, 5}}).find("versions 3 and 4"), std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 30, 1}}).find("versions 3 and 4"), std::string::npos);
  EXPECT_NE(refuses({{ItemType::Point14, 30, 3}, {ItemType::Wavepacket14, 29, 2}})
                .find("versions 3 and 4"),
            std::string::npos);
  // Version 2 (LASzip's prototype) reads as version 3, and is never written.
  EXPECT_EQ(refuses({{ItemType::Point14, 30, 2}, {ItemType::Rgb14, 6, 2}}), "accepted");
  EXPECT_NE(refuses({{ItemType::Point14, 30, 2}}, true).find("versions 3 and 4"),
            std::string::npos);
  EXPECT_EQ(refuses({{ItemType::Point14, 30, 4}, {ItemType::Byte14, 3, 3}}, true), "accepted");
}

}  // namespace
}  // namespace parallax::laz
