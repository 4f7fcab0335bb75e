// E57 reading: PDAL's test files (one scan, two scans, a pose) to the values libE57Format, the
// reference library, reads from them (its dump, pose applied, 9 decimals), and the chunked
// stream equal to the whole read.
#include <gtest/gtest.h>

#include <cmath>

#include "io/e57/e57_pages.h"
#include "io/e57/e57_reader.h"
#include "io/e57/e57_test_files.h"
#include "io/point_file.h"

namespace parallax {
namespace {

struct Expected {
  std::uint32_t scan;
  double x, y, z;
  std::uint8_t r, g, b;
  float intensity;
};

// libE57Format's values; a coordinate is within 1e-8 (its 9 printed decimals, and quantization
// steps below 2e-9 at these extents).
void expectPoints(const PointCloud& cloud, const std::vector<Expected>& expected) {
  ASSERT_EQ(cloud.count, expected.size());
  ASSERT_TRUE(cloud.hasColors());
  ASSERT_TRUE(cloud.hasIntensity());
  const ScalarColumn* scan = cloud.findScalar(column_names::kScanIndex);
  ASSERT_NE(scan, nullptr);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE("point " + std::to_string(i));
    const Expected& e = expected[i];
    EXPECT_EQ(scan->as<std::uint32_t>()[i], e.scan);
    EXPECT_NEAR(cloud.worldX(i), e.x, 1e-8);
    EXPECT_NEAR(cloud.worldY(i), e.y, 1e-8);
    EXPECT_NEAR(cloud.worldZ(i), e.z, 1e-8);
    EXPECT_EQ(cloud.colors[i], (Rgba8{e.r, e.g, e.b, 255}));
    EXPECT_NEAR(cloud.intensity[i], e.intensity, 1e-3);
  }
}

const std::vector<Expected> kA4 = {
    {0, -44.300098419, -1.132099986, 0.335799992, 0, 255, 0, 0.0f},
    {0, -44.506900787, -0.885999978, 0.328599989, 0, 255, 0, 0.0f},
    {0, -44.448699951, -0.885999978, 0.369399995, 0, 255, 0, 0.0f},
    {0, -44.952201843, -1.349300027, -0.607699990, 0, 255, 0, 0.0f},
};

TEST(E57Reader, PdalA4OneScanCartesianColourIntensity) {
  const auto path = test::e57DataFile("A4.e57");
  EXPECT_EQ(detectPointFormat(path), PointFormat("e57"));
  const PointCloud cloud = readPointFile(path);
  expectPoints(cloud, kA4);
  // What PDAL's own test asserts (its colour in 16 bits: 65535 is our 255).
  EXPECT_NEAR(cloud.worldX(0), -44.300098, 1e-6);
  EXPECT_NEAR(cloud.worldY(0), -1.132100, 1e-6);
  EXPECT_NEAR(cloud.worldZ(0), 0.335800, 1e-6);
  EXPECT_EQ(cloud.source.color, ScalarType::UInt8);
}

TEST(E57Reader, PdalB2) {
  expectPoints(readE57(test::e57DataFile("B2.e57")),
               {{0, -42.639499664, 1.872599959, 0.666700006, 255, 255, 0, 0.0f},
                {0, -42.642299652, 2.057800055, 0.510100007, 255, 255, 0, 0.0f}});
}

// Two scans: B2's points then A4's, each scan's intensity mapped from its own limits (0..0.873
// and 0..257.9 onto 0..65535).
const std::vector<Expected> kAB = {
    {0, -42.639499664, 1.872599959, 0.666700006, 255, 255, 0, 0.0f},
    {0, -42.642299652, 2.057800055, 0.510100007, 255, 255, 0, 65535.0f},
    {1, -44.300098419, -1.132099986, 0.335799992, 0, 255, 0, 0.0f},
    {1, -44.506900787, -0.885999978, 0.328599989, 0, 255, 0, 0.0f},
    {1, -44.448699951, -0.885999978, 0.369399995, 0, 255, 0, 898.263f},
    {1, -44.952201843, -1.349300027, -0.607699990, 0, 255, 0, 65535.0f},
};

TEST(E57Reader, PdalTwoScansKeepTheirIndex) {
  const auto path = test::e57DataFile("A_B.e57");
  expectPoints(readE57(path), kAB);
  E57ChunkReader reader(path);
  ASSERT_EQ(reader.header().document.scans.size(), 2u);
  EXPECT_EQ(reader.header().record_count, 6u);
  EXPECT_EQ(reader.pointCount(), 6u);
  EXPECT_FALSE(reader.header().bounds_measured);  // from the scans' cartesianBounds
}

// A4_moved holds A4 shifted in its coordinates, with no pose (libE57Format reads the same): each
// of its points is A4's plus one translation. Poses are checked on generated files
// (test_e57_writer.cpp) and against libE57Format by hand (src/io/e57/NOTES.md).
TEST(E57Reader, PdalMovedFileIsA4Shifted) {
  const auto path = test::e57DataFile("A4_moved.e57");
  const PointCloud moved = readE57(path);
  expectPoints(moved, {
                          {0, -43.467334747, 0.922503114, 0.335799992, 0, 255, 0, 0.0f},
                          {0, -43.674137115, 1.168603182, 0.328599989, 0, 255, 0, 0.0f},
                          {0, -43.615936279, 1.168603182, 0.369399995, 0, 255, 0, 0.0f},
                          {0, -44.119438171, 0.705303073, -0.607699990, 0, 255, 0, 0.0f},
                      });
  for (std::size_t i = 1; i < kA4.size(); ++i) {
    EXPECT_NEAR(moved.worldX(i) - kA4[i].x, moved.worldX(0) - kA4[0].x, 1e-6);
    EXPECT_NEAR(moved.worldY(i) - kA4[i].y, moved.worldY(0) - kA4[0].y, 1e-6);
  }
  const E57ChunkReader reader(path);
  EXPECT_EQ(reader.header().document.scans[0].pose.translation,
            (std::array<double, 3>{0.0, 0.0, 0.0}));
}

TEST(E57Reader, ChunksEqualTheWholeRead) {
  const auto path = test::e57DataFile("A_B.e57");
  const PointCloud whole = readE57(path);
  E57ChunkReader reader(path);
  reader.setQuantization(whole.quantization);
  PointCloud chunk;
  std::vector<std::size_t> sizes;
  std::size_t at = 0;
  while (reader.next(chunk, 4)) {
    sizes.push_back(chunk.count);
    for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
      EXPECT_EQ(chunk.positions[i], whole.positions[at]);
      EXPECT_EQ(chunk.colors[i], whole.colors[at]);
      EXPECT_EQ(chunk.intensity[i], whole.intensity[at]);
    }
  }
  EXPECT_EQ(sizes, (std::vector<std::size_t>{4, 2}));
  EXPECT_EQ(chunk.count, 0u);
}

TEST(E57Reader, PreviewTakesTheFirstPointsOfEachScan) {
  const PointCloud preview = readPointFilePreview(test::e57DataFile("A_B.e57"), 2);
  ASSERT_EQ(preview.count, 2u);
  const ScalarColumn* scan = preview.findScalar(column_names::kScanIndex);
  EXPECT_EQ(scan->as<std::uint32_t>()[0], 0u);
  EXPECT_EQ(scan->as<std::uint32_t>()[1], 1u);
  EXPECT_NEAR(preview.worldX(1), kAB[2].x, 1e-8);
}

TEST(E57Pages, Crc32cKnownAnswerAndPagesOfPdalFiles) {
  const std::string check = "123456789";
  EXPECT_EQ(crc32c({reinterpret_cast<const std::byte*>(check.data()), check.size()}),
            0xE3069283u);  // the CRC-32C check value
  // Every length from 0 to 2100 bytes: the interleaved streams, the 8-byte words and the tail.
  std::string bytes;
  for (std::size_t n = 0; n <= 2100; ++n) {
    const std::string_view data(bytes);
    ASSERT_EQ(crc32c({reinterpret_cast<const std::byte*>(data.data()), data.size()}),
              test::slowCrc32c(data))
        << n << " bytes";
    bytes.push_back(char(n * 131 + 7));
  }
  const std::string file = test::readBytes(test::e57DataFile("A_B.e57"));
  ASSERT_EQ(file.size() % 1024, 0u);
  for (std::size_t page = 0; page < file.size(); page += 1024) {
    const std::string_view data = std::string_view(file).substr(page, 1020);
    EXPECT_EQ(crc32c({reinterpret_cast<const std::byte*>(data.data()), data.size()}),
              test::slowCrc32c(data));
  }
}

}  // namespace
}  // namespace parallax
