// The LAZ reader on real files written by LASzip and PDAL (PARALLAX_TEST_DATA/laz): every record of every
// file with an uncompressed twin decodes to exactly the twin's bytes, and the clouds read through
// readPointFile are the twins' clouds.
#include <gtest/gtest.h>

#include "core/error.h"
#include "io/las_reader.h"
#include "io/laz_reader.h"
#include "io/laz_test_files.h"
#include "io/point_file.h"

#include <set>
#include <tuple>

namespace parallax {
namespace {

using test::lazData;

struct Twin {
  const char* laz;
  const char* las;
  int format;
  std::uint64_t points;
};

const Twin kTwins[] = {
    {"point10.las.laz", "point10.las", 0, 1065},
    {"point-time.las.laz", "point-time.las", 1, 1065},
    {"point-color.las.laz", "point-color.las", 2, 1065},
    {"point-color-time.las.laz", "point-color-time.las", 3, 1065},
    {"extrabytes.laz", "extrabytes.las", 3, 1065},
    {"1815.laz", "1815.las", 1, 1247},
    // Wave packets (WAVEPACKET13), GPS time jumps and repeats, versions 2 and 1 (items of
    // version 1: POINT10, GPSTIME11, RGB12, WAVEPACKET13); records made for Parallax, compressed
    // by LASzip (tests/data/laz/README.md).
    {"wavepacket5.laz", "wavepacket5.las", 5, 2000},
    {"wavepacket5-v1.laz", "wavepacket5.las", 5, 2000},
};

TEST(LazReader, EveryRecordEqualsTheLasTwin) {
  for (const Twin& twin : kTwins) {
    SCOPED_TRACE(twin.laz);
    const LasHeader header = readLasHeader(lazData(twin.laz));
    ASSERT_TRUE(header.laszip.has_value());
    EXPECT_EQ(header.point_format, twin.format);
    EXPECT_EQ(header.point_count, twin.points);
    const std::string decoded = test::lazRecords(lazData(twin.laz));
    const std::string expected = test::lasRecords(lazData(twin.las));
    ASSERT_EQ(decoded.size(), twin.points * header.record_length);
    EXPECT_EQ(test::firstDifferentRecord(decoded, expected, header.record_length), -1);
  }
}

void expectSameCloud(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.count, b.count);
  EXPECT_EQ(a.quantization, b.quantization);
  EXPECT_EQ(a.bounds.min, b.bounds.min);
  EXPECT_EQ(a.bounds.max, b.bounds.max);
  EXPECT_EQ(a.source.color, b.source.color);
  for (std::size_t i = 0; i < a.count; ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << i;
  ASSERT_EQ(a.colors.size(), b.colors.size());
  for (std::size_t i = 0; i < a.colors.size(); ++i) ASSERT_EQ(a.colors[i], b.colors[i]) << i;
  for (std::size_t i = 0; i < a.count; ++i) ASSERT_EQ(a.intensity[i], b.intensity[i]) << i;
  for (std::size_t i = 0; i < a.count; ++i) {
    ASSERT_EQ(a.classification[i], b.classification[i]) << i;
  }
  ASSERT_EQ(a.scalars.size(), b.scalars.size());
  for (std::size_t c = 0; c < a.scalars.size(); ++c) {
    EXPECT_EQ(a.scalars[c].name, b.scalars[c].name);
    EXPECT_EQ(a.scalars[c].type, b.scalars[c].type);
    ASSERT_EQ(a.scalars[c].data.size(), b.scalars[c].data.size());
    EXPECT_EQ(
        std::memcmp(a.scalars[c].data.data(), b.scalars[c].data.data(), a.scalars[c].data.size()),
        0)
        << a.scalars[c].name;
  }
}

TEST(LazReader, CloudsEqualTheTwinsOnEveryCoreAndOnOne) {
  for (const Twin& twin : kTwins) {
    SCOPED_TRACE(twin.laz);
    EXPECT_EQ(detectPointFormat(lazData(twin.laz)), PointFormat::Laz);
    const PointCloud las = readLas(lazData(twin.las));
    expectSameCloud(readPointFile(lazData(twin.laz)), las);
    expectSameCloud(readLaz(lazData(twin.laz), {.parallel = false}), las);
    // readLas reads LAZ too (the header says which).
    expectSameCloud(readLas(lazData(twin.laz)), las);
    const std::string bytes = test::fileBytes(lazData(twin.laz));
    expectSameCloud(readLazFromMemory(std::as_bytes(std::span(bytes.data(), bytes.size())), "m"),
                    las);
  }
}

// The COPC files (layered, variable chunks) through the file layer: LASzip's records, whose
// checksums tests/io/test_laz_layered.cpp states (FNV-1a 64 over every record), and the same
// cloud on every core and on one.
TEST(LazReader, CopcFilesDecodeAsLaszipThroughTheFileLayer) {
  const std::pair<const char*, std::uint64_t> files[] = {
      {"simple.copc.laz", 0x2b9c1be162ecbe35ull}, {"ellipsoid.copc.laz", 0x53a386236f11ab8dull}};
  for (const auto& [name, checksum] : files) {
    SCOPED_TRACE(name);
    const std::string records = test::lazRecords(lazData(name));
    std::uint64_t hash = 0xcbf29ce484222325ull;
    for (char c : records) {
      hash ^= std::uint64_t(std::uint8_t(c));
      hash *= 0x100000001b3ull;
    }
    EXPECT_EQ(hash, checksum);
    const PointCloud all = readLaz(lazData(name));
    expectSameCloud(readLaz(lazData(name), {.parallel = false}), all);
    EXPECT_EQ(summarizeLaz(lazData(name)).chunk_size, 0u);  // variable
  }
}

TEST(LazReader, ChunkReaderGivesTheSamePointsInBatches) {
  const PointCloud whole = readLaz(lazData("ellipsoid.laz"));
  ASSERT_EQ(whole.count, 100000u);
  // 100 000 points in chunks of 50 000: batches that end inside chunks and span two.
  for (std::size_t batch :
       {std::size_t(7), std::size_t(30000), std::size_t(64000), std::size_t(200000)}) {
    SCOPED_TRACE(batch);
    LazChunkReader reader(lazData("ellipsoid.laz"));
    EXPECT_EQ(reader.pointCount(), 100000u);
    PointCloud chunk;
    std::size_t at = 0;
    std::size_t calls = 0;
    while (reader.next(chunk, batch)) {
      ++calls;
      ASSERT_LE(chunk.count, batch);
      for (std::size_t i = 0; i < chunk.count; ++i) {
        ASSERT_EQ(chunk.positions[i], whole.positions[at + i]) << at + i;
        ASSERT_EQ(chunk.colors[i], whole.colors[at + i]) << at + i;
      }
      const ScalarColumn* time = chunk.findScalar(las_names::kGpsTime);
      ASSERT_NE(time, nullptr);
      EXPECT_EQ(
          std::memcmp(time->data.data(),
                      whole.findScalar(las_names::kGpsTime)->data.data() + at * 8, chunk.count * 8),
          0);
      at += chunk.count;
      if (batch == 7 && calls == 3000) break;  // enough of the tiny batches
    }
    if (batch != 7) {
      EXPECT_EQ(at, whole.count);
    }
    EXPECT_EQ(chunk.count, batch == 7 ? 7u : 0u);
  }
}

TEST(LazReader, PreviewIsASampleOfTheFile) {
  const PointCloud whole = readLaz(lazData("ellipsoid.laz"));
  const PointCloud preview = readLazPreview(lazData("ellipsoid.laz"), 20000);
  EXPECT_GT(preview.count, 10000u);
  EXPECT_LE(preview.count, 20000u);
  EXPECT_EQ(preview.quantization, whole.quantization);
  EXPECT_EQ(preview.scalars.size(), whole.scalars.size());
  // Every preview point is a point of the file (positions are unique enough to look up).
  std::set<std::tuple<int, int, int>> all;
  for (std::size_t i = 0; i < whole.count; ++i) {
    all.insert({whole.positions[i].x, whole.positions[i].y, whole.positions[i].z});
  }
  for (std::size_t i = 0; i < preview.count; ++i) {
    ASSERT_TRUE(all.count({preview.positions[i].x, preview.positions[i].y, preview.positions[i].z}))
        << i;
  }
  // Small enough: the whole file.
  EXPECT_EQ(readLazPreview(lazData("point10.las.laz"), 5000).count, 1065u);
}

TEST(LasPreview, RunsOfRecordsSpreadOverTheFile) {
  const PointCloud whole = readLas(lazData("point-color-time.las"));
  // 1065 points, 256 wanted: 4 runs of 64 records, 266 records apart.
  const PointCloud preview = readPointFilePreview(lazData("point-color-time.las"), 256);
  ASSERT_EQ(preview.count, 256u);
  EXPECT_EQ(preview.quantization, whole.quantization);
  EXPECT_EQ(preview.source.color, whole.source.color);
  for (std::size_t run = 0; run < 4; ++run) {
    for (std::size_t i = 0; i < 64; ++i) {
      ASSERT_EQ(preview.positions[run * 64 + i], whole.positions[run * 266 + i]);
      ASSERT_EQ(preview.colors[run * 64 + i], whole.colors[run * 266 + i]);
    }
  }
  EXPECT_EQ(readPointFilePreview(lazData("point-color-time.las"), 5000).count, 1065u);
  EXPECT_TRUE(hasPointFilePreview(PointFormat::Laz));
  EXPECT_FALSE(hasPointFilePreview(PointFormat::Text));
}

TEST(LazReader, SummaryNamesCompressionChunksAndItems) {
  const LazSummary summary = summarizeLaz(lazData("extrabytes.laz"));
  EXPECT_EQ(summary.compressor, 2);
  EXPECT_EQ(summary.compressor_name, "point-wise chunked");
  EXPECT_EQ(summary.chunk_size, 50000u);
  EXPECT_EQ(summary.chunks, 1u);
  EXPECT_EQ(summary.laszip_version, "2.2.0");
  ASSERT_EQ(summary.items.size(), 4u);
  EXPECT_EQ(summary.items[0], "POINT10 v2 (20 bytes)");
  EXPECT_EQ(summary.items[3], "BYTE v2 (27 bytes)");
  EXPECT_FALSE(summary.compatibility_mode);
  EXPECT_TRUE(summary.table_note.empty());
}

}  // namespace
}  // namespace parallax
