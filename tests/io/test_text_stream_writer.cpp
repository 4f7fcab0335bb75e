// TextStreamWriter: the bytes writeText gives the whole cloud, a batch at a time, in memory for
// one batch.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <iterator>
#include <string>

#include "core/point_cloud.h"
#include "core/point_gather.h"
#include "io/point_file.h"
#include "io/text_writer.h"
#include "support/allocation_counter.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::fileBytes;

PointCloud numberedCloud(std::size_t points) {
  PointCloud cloud;
  cloud.count = points;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.positions = Column<Int3>(points);
  cloud.normals = Column<Float3>(points);
  ScalarColumn distance{"distance", ScalarType::Float32, ByteBuffer(points * 4)};
  for (std::size_t i = 0; i < points; ++i) {
    cloud.positions[i] = {int(i % 1000), int(i / 1000), int(i % 7)};
    cloud.normals[i] = {0.0f, float(i % 3) * 0.5f, 1.0f};
    distance.as<float>()[i] = float(i) * 0.25f;
  }
  cloud.scalars.push_back(std::move(distance));
  return cloud;
}

TEST(TextStreamWriter, BatchesGiveTheBytesOfTheWholeCloud) {
  test::TempDir dir;
  const PointCloud cloud = numberedCloud(100000);
  for (const char* name : {"out.xyz", "out.csv", "out.pts"}) {
    SCOPED_TRACE(name);
    writeText(cloud, dir / (std::string("whole_") + name), textOptionsForPath(name));
    TextStreamWriter writer(dir / name, slicePoints(cloud, 0, 1), cloud.count,
                            textOptionsForPath(name));
    // Uneven batches, one of them empty.
    std::size_t first = 0;
    for (std::size_t size : {0u, 1u, 4095u, 60000u, 35904u}) {
      writer.write(slicePoints(cloud, first, size));
      first += size;
    }
    ASSERT_EQ(first, cloud.count);
    writer.finish();
    EXPECT_EQ(fileBytes(dir / name), fileBytes(dir / (std::string("whole_") + name)));
  }
}

TEST(TextWriter, PositionsKeepTheOffsetsDecimals) {
  // LAS offsets with more decimals than the scale (1815.las of the LAZ test set: scale 1e-5,
  // offsets 2014969.123479 6493024.64672738 76.552602795884): every digit of offset + k * scale
  // is printed, with the offset's decimals (x, y), or as the shortest digits of the double where
  // the offset has more than 9 (z).
  PointCloud cloud;
  cloud.count = 1;
  cloud.quantization.scale = {1e-5, 1e-5, 1e-5};
  cloud.quantization.offset = {2014969.123479, 6493024.64672738, 76.552602795884};
  cloud.positions = Column<Int3>(1);
  cloud.positions[0] = {-84318401, -2207401, 2763};
  test::TempDir dir;
  writeText(cloud, dir / "out.csv", textOptionsForPath("out.csv"));
  const double z = cloud.worldZ(0);
  char digits[64];
  const std::string z_text(digits, std::to_chars(digits, digits + sizeof digits, z).ptr);
  EXPECT_EQ(fileBytes(dir / "out.csv"), "x,y,z\n2014125.939469,6493002.57271738," + z_text + "\n");
  EXPECT_EQ(std::stod(z_text), z);
}

TEST(TextStreamWriter, HoldsABatchNotTheFile) {
  // 2 M points, about 70 MB of text, written in batches of 65 536 points: no allocation of
  // 8 MB (a batch's lines are about 2.3 MB).
  test::TempDir dir;
  constexpr std::size_t kPoints = 2000000, kBatch = 65536;
  const PointCloud cloud = numberedCloud(kPoints);
  const auto path = dir / "out.xyz";
  std::uint64_t largest = 0;
  {
    test::AllocationScope allocations;
    TextStreamWriter writer(path, slicePoints(cloud, 0, 1), kPoints);
    for (std::size_t first = 0; first < kPoints; first += kBatch) {
      writer.write(slicePoints(cloud, first, std::min(kBatch, kPoints - first)));
    }
    writer.finish();
    largest = allocations.largest();
  }
  EXPECT_LT(largest, std::uint64_t(8) << 20);
  EXPECT_GT(std::filesystem::file_size(path), std::uint64_t(60) << 20);
  const PointCloud back = readPointFile(path);
  ASSERT_EQ(back.count, kPoints);
  EXPECT_EQ(back.worldX(kPoints - 1), cloud.worldX(kPoints - 1));
  EXPECT_EQ(back.findScalar("distance")->valueAsDouble(kPoints - 1), (kPoints - 1) * 0.25);
}

TEST(TextStreamWriter, FewerPointsThanAnnouncedIsAnErrorAndLeavesNoFile) {
  test::TempDir dir;
  const PointCloud cloud = numberedCloud(10);
  {
    TextStreamWriter writer(dir / "out.pts", cloud, 11, textOptionsForPath("out.pts"));
    writer.write(cloud);
    EXPECT_THROW(writer.finish(), std::logic_error);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.pts"));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace parallax
