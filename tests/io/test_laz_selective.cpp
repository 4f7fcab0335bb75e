// Selective decoding of layered LAZ chunks (ChunkDecoder::selectFields): the fields asked for come
// out exactly as a full decode gives them, whatever else is skipped, on every layered file of
// PARALLAX_TEST_DATA/laz and on chunks Parallax's own encoder writes (formats 6-10, several
// scanner channels, item versions 3 and 4, extra bytes).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/laz/layered_codec.h"
#include "laz_synthetic_points.h"
#include "laz_test_file.h"
#include "support/test_data.h"

namespace parallax::laz {
namespace {

using testing::LazTestFile;
using testing::makeSyntheticRecords;
using testing::readLazTestFile;

// For each byte of a record, the fields:: group it belongs to (0: always decoded), from the LAS
// 1.4 R15 layouts (tables 14-18) and the items that follow POINT14.
std::vector<std::uint32_t> byteGroups(const std::vector<LazItem>& items) {
  std::vector<std::uint32_t> groups(30, 0);  // x y z (0-11) and the returns byte (14)
  groups[12] = groups[13] = fields::kIntensity;
  groups[16] = fields::kClassification;
  groups[17] = fields::kUserData;
  groups[18] = groups[19] = fields::kScanAngle;
  groups[20] = groups[21] = fields::kPointSource;
  for (std::size_t b = 22; b < 30; ++b) groups[b] = fields::kGpsTime;
  // Byte 15 mixes the flags (bits 0-3, 6, 7) with the scanner channel (bits 4-5): compared apart.
  for (std::size_t i = 1; i < items.size(); ++i) {
    switch (items[i].type) {
      case ItemType::Rgb14:
        groups.insert(groups.end(), 6, fields::kRgb);
        break;
      case ItemType::RgbNir14:
        groups.insert(groups.end(), 6, fields::kRgb);
        groups.insert(groups.end(), 2, fields::kNir);
        break;
      case ItemType::Wavepacket14:
        groups.insert(groups.end(), 29, fields::kWavePacket);
        break;
      default:
        groups.insert(groups.end(), items[i].size, fields::kExtraBytes);
        break;
    }
  }
  return groups;
}

// The subsets tried: positions only, each group alone, all but each group, and what a viewer
// asks for (colour, intensity and classification).
std::vector<std::uint32_t> subsets() {
  std::vector<std::uint32_t> s{fields::kPositionsOnly,
                               fields::kRgb | fields::kIntensity | fields::kClassification};
  for (std::uint32_t g = 1; g <= fields::kAll; g <<= 1) {
    s.push_back(g);
    s.push_back(fields::kAll & ~g);
  }
  return s;
}

struct Chunk {
  std::span<const std::byte> bytes;
  std::size_t points;
};

std::vector<std::byte> decodeChunks(ChunkDecoder& decoder, const std::vector<Chunk>& chunks,
                                    std::size_t points, std::uint32_t wanted) {
  decoder.selectFields(wanted);
  std::vector<std::byte> records(points * decoder.recordLength());
  std::size_t at = 0;
  for (const Chunk& c : chunks) {
    decoder.decode(c.bytes, c.points, records.data() + at);
    at += c.points * decoder.recordLength();
  }
  return records;
}

// Decodes the chunks in full, then once per subset through the same decoder object (a decoder
// switches subsets between chunks), and compares every byte the subset asked for.
void expectSelectiveMatchesFull(const std::vector<LazItem>& items, const std::vector<Chunk>& chunks,
                                std::size_t points) {
  auto decoder = makeLayeredDecoder(items);
  const std::size_t length = decoder->recordLength();
  const std::vector<std::uint32_t> groups = byteGroups(items);
  ASSERT_EQ(groups.size(), length);
  const std::vector<std::byte> full = decodeChunks(*decoder, chunks, points, fields::kAll);
  for (std::uint32_t wanted : subsets()) {
    SCOPED_TRACE("fields " + std::to_string(wanted));
    const std::vector<std::byte> part = decodeChunks(*decoder, chunks, points, wanted);
    std::size_t compared = 0;
    for (std::size_t p = 0; p < points; ++p) {
      const std::byte* a = full.data() + p * length;
      const std::byte* b = part.data() + p * length;
      for (std::size_t i = 0; i < length; ++i) {
        if (i == 15) {
          // The channel (bits 4-5) always; the flags (the rest) when asked.
          const unsigned mask = (wanted & fields::kFlags) ? 0xFFu : 0x30u;
          ASSERT_EQ(unsigned(a[i]) & mask, unsigned(b[i]) & mask) << "point " << p << " byte 15";
          continue;
        }
        if (groups[i] != 0 && (wanted & groups[i]) == 0) continue;
        ASSERT_EQ(a[i], b[i]) << "point " << p << " byte " << i;
        ++compared;
      }
    }
    EXPECT_GE(compared, points * 12) << "the positions at least were compared";
  }
  // And back to everything: the same records as the first full decode.
  EXPECT_EQ(decodeChunks(*decoder, chunks, points, fields::kAll), full);
}

TEST(LazSelective, EveryLayeredTestFileDecodesTheAskedFieldsAsAFullDecode) {
  const std::filesystem::path folder = test::testDataFile("laz/simple.copc.laz").parent_path();
  std::size_t layered_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".laz") continue;
    const LazTestFile f = readLazTestFile(entry.path().string());
    if (f.vlr.compressor != 3) continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++layered_files;
    std::vector<Chunk> chunks;
    for (const auto& c : f.chunks) chunks.push_back({f.chunkBytes(c), std::size_t(c.points)});
    expectSelectiveMatchesFull(f.vlr.items, chunks, std::size_t(f.point_count));
  }
  // ellipsoid.copc.laz and simple.copc.laz at least.
  EXPECT_GE(layered_files, 2u);
}

TEST(LazSelective, ParallaxChunksOfEveryLayeredFormatDecodeTheAskedFieldsAsAFullDecode) {
  for (int format = 6; format <= 10; ++format) {
    for (std::uint16_t version : {3, 4}) {
      SCOPED_TRACE("format " + std::to_string(format) + " version " + std::to_string(version));
      const std::size_t extra = format == 7 ? 3 : 0;
      const std::vector<std::byte> records = makeSyntheticRecords(
          {.format = format, .extra_bytes = extra, .count = 3000, .seed = 31, .quiet_span = 500});
      const std::vector<LazItem> items = testing::layeredItemsFor(format, extra, version);
      auto encoder = makeLayeredEncoder(items);
      const std::size_t length = encoder->recordLength();
      const std::size_t count = records.size() / length;
      // Chunks of 700: some hold quiet spans, whose unchanged layers are empty.
      std::vector<std::vector<std::uint8_t>> bytes;
      std::vector<std::size_t> sizes;
      for (std::size_t at = 0; at < count; at += 700) {
        bytes.emplace_back();
        sizes.push_back(std::min<std::size_t>(700, count - at));
        encoder->encode(records.data() + at * length, sizes.back(), bytes.back());
      }
      std::vector<Chunk> chunks;
      for (std::size_t i = 0; i < bytes.size(); ++i) {
        chunks.push_back({std::as_bytes(std::span(bytes[i])), sizes[i]});
      }
      expectSelectiveMatchesFull(items, chunks, count);
      // The full decode is the source itself.
      auto decoder = makeLayeredDecoder(items);
      EXPECT_EQ(decodeChunks(*decoder, chunks, count, fields::kAll), records);
    }
  }
}

TEST(LazSelective, SkippedLayersAreNotRead) {
  // A chunk whose skipped layers are garbage still decodes what was asked: those bytes are never
  // read. (Flipping bytes of the GPS time layer changes nothing when GPS time is not asked.)
  const std::vector<std::byte> records =
      makeSyntheticRecords({.format = 6, .count = 500, .seed = 4});
  const std::vector<LazItem> items{{ItemType::Point14, 30, 3}};
  auto encoder = makeLayeredEncoder(items);
  std::vector<std::uint8_t> chunk;
  encoder->encode(records.data(), 500, chunk);
  std::uint32_t sizes[9];
  std::memcpy(sizes, chunk.data() + 30 + 4, sizeof sizes);
  ASSERT_GT(sizes[8], 8u) << "the GPS time layer is present";
  std::size_t gps_at = 30 + 4 + sizeof sizes;
  for (int i = 0; i < 8; ++i) gps_at += sizes[i];
  std::vector<std::uint8_t> broken = chunk;
  for (std::size_t i = 0; i < sizes[8]; ++i) broken[gps_at + i] ^= 0x5A;

  auto decoder = makeLayeredDecoder(items);
  std::vector<std::byte> full(500 * 30), part(500 * 30);
  decoder->decode(std::as_bytes(std::span(chunk)), 500, full.data());
  EXPECT_EQ(full, records);
  decoder->selectFields(fields::kAll & ~fields::kGpsTime);
  decoder->decode(std::as_bytes(std::span(broken)), 500, part.data());
  for (std::size_t p = 0; p < 500; ++p) {
    ASSERT_EQ(std::memcmp(full.data() + p * 30, part.data() + p * 30, 22), 0) << "point " << p;
  }
  // Asked for, the broken layer is read: the chunk is refused or its GPS times differ.
  decoder->selectFields(fields::kAll);
  bool refused = false;
  try {
    decoder->decode(std::as_bytes(std::span(broken)), 500, part.data());
  } catch (const ChunkCorrupt&) {
    refused = true;
  }
  EXPECT_TRUE(refused || part != full);
}

}  // namespace
}  // namespace parallax::laz
