// The LAZ writer: what it writes decodes to exactly the records the LAS writer writes for the same
// cloud, in chunks of the size asked for, with a chunk table; clouds survive LAS -> LAZ and
// PLY -> LAZ -> PLY exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "io/las_reader.h"
#include "io/las_writer.h"
#include "io/laz_reader.h"
#include "io/laz_test_files.h"
#include "io/laz_writer.h"
#include "io/ply_reader.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::lazData;

const char* const kSources[] = {"point10.las",          "point-time.las", "point-color.las",
                                "point-color-time.las", "extrabytes.las", "1815.las"};

TEST(LazWriter, RecordsAreTheLasWritersRecords) {
  test::TempDir dir;
  for (const char* name : kSources) {
    SCOPED_TRACE(name);
    const PointCloud cloud = readLas(lazData(name));
    writeLas(cloud, dir / "out.las");
    for (std::uint32_t chunk : {50000u, 100u, 1u}) {
      SCOPED_TRACE(chunk);
      writeLaz(cloud, dir / "out.laz", {.chunk_points = chunk});
      const LasHeader las = readLasHeader(dir / "out.las");
      const LasHeader laz = readLasHeader(dir / "out.laz");
      ASSERT_TRUE(laz.laszip.has_value());
      EXPECT_EQ(laz.laszip->compressor, 2);
      EXPECT_EQ(laz.laszip->chunk_size, chunk);
      for (const laz::LazItem& item : laz.laszip->items) EXPECT_EQ(item.version, 2);
      EXPECT_EQ(laz.point_format, las.point_format);
      EXPECT_EQ(laz.point_count, las.point_count);
      EXPECT_EQ(laz.bounds.min, las.bounds.min);
      EXPECT_EQ(laz.bounds.max, las.bounds.max);
      EXPECT_EQ(summarizeLaz(dir / "out.laz").chunks, (las.point_count + chunk - 1) / chunk);
      const std::string expected = test::lasRecords(dir / "out.las");
      EXPECT_EQ(test::firstDifferentRecord(test::lazRecords(dir / "out.laz"), expected,
                                           las.record_length),
                -1);
    }
  }
}

TEST(LazWriter, PointFileDispatchWritesLaz) {
  test::TempDir dir;
  const PointCloud cloud = readLas(lazData("point-color-time.las"));
  EXPECT_EQ(formatForExtension(dir / "x.LAZ"), PointFormat::Laz);
  writePointFile(cloud, dir / "x.laz", {.laz_chunk_points = 500});
  EXPECT_EQ(detectPointFormat(dir / "x.laz"), PointFormat::Laz);
  EXPECT_EQ(summarizeLaz(dir / "x.laz").chunks, 3u);
  const PointCloud back = readPointFile(dir / "x.laz");
  ASSERT_EQ(back.count, cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    ASSERT_EQ(back.positions[i], cloud.positions[i]);
    ASSERT_EQ(back.colors[i], cloud.colors[i]);
  }
  EXPECT_TRUE(describeWriteLosses(cloud, dir / "x.laz").empty());
}

TEST(LazWriter, EmptyCloudWritesAValidFile) {
  test::TempDir dir;
  PointCloud empty;
  writeLaz(empty, dir / "empty.laz");
  EXPECT_EQ(readLaz(dir / "empty.laz").count, 0u);
  EXPECT_EQ(summarizeLaz(dir / "empty.laz").chunks, 0u);
}

TEST(LazWriter, PlyToLazToPlyIsExact) {
  test::TempDir dir;
  // A PLY as photogrammetry tools write it: float positions and normals, 8-bit colours.
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 500\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (int i = 0; i < 500; ++i) {
    char line[200];
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f %.6f %.6f %.6f %d %d %d\n", 100.0 + 0.37 * i,
                  -20.0 + std::sin(i) * 5, 3.0 + 0.01 * (i % 17), std::cos(i * 0.1),
                  std::sin(i * 0.1), 0.25, i % 256, (i * 7) % 256, (i * 13) % 256);
    ply += line;
  }
  const PointCloud source = readPly(dir.write("in.ply", ply));
  writeLaz(source, dir / "mid.laz");
  writePly(readLaz(dir / "mid.laz"), dir / "out.ply");
  const PointCloud back = readPly(dir / "out.ply");
  ASSERT_EQ(back.count, source.count);
  ASSERT_TRUE(back.hasNormals());
  ASSERT_TRUE(back.hasColors());
  for (std::size_t i = 0; i < source.count; ++i) {
    ASSERT_EQ(back.worldX(i), source.worldX(i)) << i;
    ASSERT_EQ(back.worldY(i), source.worldY(i)) << i;
    ASSERT_EQ(back.worldZ(i), source.worldZ(i)) << i;
    ASSERT_EQ(back.normals[i].x, source.normals[i].x) << i;
    ASSERT_EQ(back.normals[i].y, source.normals[i].y) << i;
    ASSERT_EQ(back.normals[i].z, source.normals[i].z) << i;
    ASSERT_EQ(back.colors[i], source.colors[i]) << i;
  }
}

}  // namespace
}  // namespace parallax
