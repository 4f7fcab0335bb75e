// The specialised chunk decoders (point-wise POINT10 + GPSTIME11 and/or RGB12 version 2; layered
// chunks one item at a time) against the general path (every item through its virtual decoder,
// point by point): the same file decoded both ways gives the same bytes, for every LAZ file of
// PARALLAX_TEST_DATA/laz and tests/data/laz and for chunks Parallax's own encoders write.
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
#include "io/laz/pointwise_codec.h"
#include "laz_synthetic_points.h"
#include "laz_test_file.h"
#include "support/test_data.h"

namespace parallax::laz {
namespace {

using testing::layeredItemsFor;
using testing::LazTestFile;
using testing::makeSyntheticRecords;
using testing::readLazTestFile;

std::unique_ptr<ChunkDecoder> decoderFor(int compressor, const std::vector<LazItem>& items,
                                         DecoderPath path) {
  return compressor == 3 ? makeLayeredDecoder(items, path) : makePointwiseDecoder(items, path);
}

std::vector<std::byte> decodeFile(const LazTestFile& f, DecoderPath path) {
  auto decoder = decoderFor(f.vlr.compressor, f.vlr.items, path);
  std::vector<std::byte> records(f.point_count * f.record_length);
  std::size_t at = 0;
  for (const auto& c : f.chunks) {
    decoder->decode(f.chunkBytes(c), c.points, records.data() + at);
    at += c.points * f.record_length;
  }
  return records;
}

void expectSameRecords(const std::vector<std::byte>& general,
                       const std::vector<std::byte>& specialised, std::size_t length) {
  ASSERT_EQ(general.size(), specialised.size());
  for (std::size_t p = 0; p * length < general.size(); ++p) {
    for (std::size_t i = 0; i < length; ++i) {
      ASSERT_EQ(general[p * length + i], specialised[p * length + i])
          << "point " << p << " byte " << i;
    }
  }
}

TEST(LazSpecialised, EveryTestFileDecodesAsTheGeneralPath) {
  std::vector<std::filesystem::path> files;
  for (const std::filesystem::path& folder :
       {test::testDataFile("laz/simple.copc.laz").parent_path(),
        std::filesystem::path(PARALLAX_LAZ_DATA)}) {
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      if (entry.path().extension() == ".laz") files.push_back(entry.path());
    }
  }
  // Formats 0-3 (the specialised point-wise sets), 5 (general only) and 7 (layered).
  std::vector<int> formats;
  for (const std::filesystem::path& path : files) {
    SCOPED_TRACE(path.filename().string());
    const LazTestFile f = readLazTestFile(path.string());
    formats.push_back(f.point_format);
    const std::vector<std::byte> general = decodeFile(f, DecoderPath::kGeneral);
    const std::vector<std::byte> specialised = decodeFile(f, DecoderPath::kSpecialised);
    expectSameRecords(general, specialised, f.record_length);
  }
  for (int format : {0, 1, 2, 3, 7}) {
    EXPECT_NE(std::find(formats.begin(), formats.end(), format), formats.end())
        << "a test file of format " << format;
  }
}

TEST(LazSpecialised, ParallaxPointwiseChunksDecodeAsTheGeneralPath) {
  // The real format-3 file's records re-encoded by Parallax in chunks of 1 000, and the same
  // records cut to formats 0-2 (their POINT10, GPS time and RGB parts).
  const LazTestFile f = readLazTestFile(test::testDataFile("laz/ellipsoid.laz").string());
  ASSERT_EQ(f.point_format, 3);
  const std::vector<std::byte> source = decodeFile(f, DecoderPath::kGeneral);
  const std::size_t n = f.point_count;
  ASSERT_GT(n, 10000u);
  struct Set {
    bool gps, rgb;
  };
  for (Set set : {Set{false, false}, Set{true, false}, Set{false, true}, Set{true, true}}) {
    SCOPED_TRACE(std::string("gps ") + (set.gps ? "yes" : "no") + ", rgb " +
                 (set.rgb ? "yes" : "no"));
    std::vector<LazItem> items{{ItemType::Point10, 20, 2}};
    if (set.gps) items.push_back({ItemType::GpsTime11, 8, 2});
    if (set.rgb) items.push_back({ItemType::Rgb12, 6, 2});
    const std::size_t length = 20 + (set.gps ? 8 : 0) + (set.rgb ? 6 : 0);
    std::vector<std::byte> records(n * length);
    for (std::size_t p = 0; p < n; ++p) {
      const std::byte* in = source.data() + p * 34;
      std::byte* out = records.data() + p * length;
      std::memcpy(out, in, 20);
      if (set.gps) std::memcpy(out + 20, in + 20, 8);
      if (set.rgb) std::memcpy(out + length - 6, in + 28, 6);
    }
    auto encoder = makePointwiseEncoder(items);
    std::vector<std::vector<std::uint8_t>> chunks;
    for (std::size_t at = 0; at < n; at += 1000) {
      chunks.emplace_back();
      encoder->encode(records.data() + at * length, std::min<std::size_t>(1000, n - at),
                      chunks.back());
    }
    std::vector<std::byte> decoded[2];
    for (DecoderPath path : {DecoderPath::kGeneral, DecoderPath::kSpecialised}) {
      auto decoder = makePointwiseDecoder(items, path);
      std::vector<std::byte>& out = decoded[path == DecoderPath::kGeneral ? 0 : 1];
      out.resize(n * length);
      for (std::size_t c = 0; c < chunks.size(); ++c) {
        decoder->decode(std::as_bytes(std::span(chunks[c])),
                        std::min<std::size_t>(1000, n - c * 1000), out.data() + c * 1000 * length);
      }
    }
    expectSameRecords(decoded[0], decoded[1], length);
    EXPECT_EQ(decoded[1], records);
  }
}

TEST(LazSpecialised, ParallaxLayeredChunksDecodeAsTheGeneralPath) {
  for (int format = 6; format <= 10; ++format) {
    for (std::uint16_t version : {3, 4}) {
      SCOPED_TRACE("format " + std::to_string(format) + " version " + std::to_string(version));
      const std::size_t extra = format == 6 ? 2 : 0;
      const std::vector<std::byte> records = makeSyntheticRecords(
          {.format = format, .extra_bytes = extra, .count = 2500, .seed = 9, .quiet_span = 400});
      const std::vector<LazItem> items = layeredItemsFor(format, extra, version);
      auto encoder = makeLayeredEncoder(items);
      const std::size_t length = encoder->recordLength();
      std::vector<std::uint8_t> chunk;
      encoder->encode(records.data(), 2500, chunk);
      std::vector<std::byte> general(2500 * length), specialised(2500 * length);
      makeLayeredDecoder(items, DecoderPath::kGeneral)
          ->decode(std::as_bytes(std::span(chunk)), 2500, general.data());
      makeLayeredDecoder(items, DecoderPath::kSpecialised)
          ->decode(std::as_bytes(std::span(chunk)), 2500, specialised.data());
      expectSameRecords(general, specialised, length);
      EXPECT_EQ(specialised, records);
    }
  }
}

TEST(LazSpecialised, BrokenChunksAreReportedAtTheSamePointOnBothPaths) {
  const LazTestFile f = readLazTestFile(test::testDataFile("laz/ellipsoid.laz").string());
  ASSERT_FALSE(f.chunks.empty());
  const auto& c = f.chunks[0];
  std::vector<std::byte> cut(f.chunkBytes(c).begin(), f.chunkBytes(c).end());
  cut.resize(cut.size() / 2);
  std::size_t reported[2] = {0, 0};
  for (DecoderPath path : {DecoderPath::kGeneral, DecoderPath::kSpecialised}) {
    std::vector<std::byte> out(c.points * f.record_length);
    try {
      makePointwiseDecoder(f.vlr.items, path)->decode(cut, c.points, out.data());
      ADD_FAILURE() << "a chunk cut in half decoded";
    } catch (const ChunkCorrupt& e) {
      reported[path == DecoderPath::kGeneral ? 0 : 1] = e.point();
    }
  }
  EXPECT_GT(reported[0], 0u);
  EXPECT_EQ(reported[0], reported[1]);
}

}  // namespace
}  // namespace parallax::laz
