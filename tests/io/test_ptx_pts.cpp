// PTX: two scans with their transforms (values computed here by hand), zero points, scan poses,
// the writer's round trip, bad input; PTS: count lines, with and without colour; PDAL's files.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "io/point_file.h"
#include "io/pts_reader.h"
#include "io/ptx_reader.h"
#include "io/ptx_writer.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

const std::filesystem::path kPtxData = PARALLAX_SHARED_DATA "/formats";

// Scan 0: identity pose, 2 x 1 grid. Scan 1: a quarter turn about z (x -> y, y -> -x) and a
// translation of (100, 200, 10), written as PTX writes it (translation in the last row), 2 x 2
// grid with one zero point.
const std::string kTwoScans =
    "2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
    "1.5 2.25 -3 0.5 10 20 30\n"
    "4 5 6 0.25 40 50 60\n"
    "2\n2\n100 200 10\n0 1 0\n-1 0 0\n0 0 1\n0 1 0 0\n-1 0 0 0\n0 0 1 0\n100 200 10 1\n"
    "1 0 0 1 1 2 3\n"
    "0 0 0 0.5 0 0 0\n"
    "0 2 0.5 0.75 4 5 6\n"
    "-1 -1 -1 0 7 8 9\n";

TEST(PtxReader, IntensityOnZeroToOneIsWrittenToLasOnZeroTo65535) {
  // PTX's intensity is a float in 0..1: a LAS written from it had every point's intensity 0 (or
  // 1), rounded to 16-bit integers; it is mapped onto 0..65535.
  const PointCloud cloud = readPtxFromMemory(test::asBytes(kTwoScans), "t.ptx", {});
  EXPECT_EQ(cloud.source.intensity_full_scale, 1.0);
  test::TempDir dir;
  for (const char* name : {"t.las", "t.laz"}) {
    SCOPED_TRACE(name);
    writePointFile(cloud, dir / name);
    const PointCloud las = readPointFile(dir / name);
    ASSERT_EQ(las.count, cloud.count);
    for (std::size_t i = 0; i < cloud.count; ++i) {
      EXPECT_EQ(las.intensity[i], float(std::nearbyint(double(cloud.intensity[i]) * 65535.0))) << i;
    }
    EXPECT_EQ(las.intensity[0], 32768.0f);  // 0.5 * 65535 = 32767.5, to even
    EXPECT_EQ(las.intensity[3], 49151.0f);  // 0.75 * 65535 = 49151.25
    EXPECT_EQ(las.intensity[2], 65535.0f);
  }
}

TEST(PtxReader, TwoScansWithTransformsAndZeroPointsSkipped) {
  std::vector<PtxScan> scans;
  const PointCloud cloud = readPtxFromMemory(test::asBytes(kTwoScans), "t.ptx", {.scans = &scans});
  ASSERT_EQ(cloud.count, 5u);  // 2 + 4 - 1 zero point
  const ScalarColumn* scan = cloud.findScalar(column_names::kScanIndex);
  ASSERT_NE(scan, nullptr);
  // Scan 0 as written.
  EXPECT_NEAR(cloud.worldX(0), 1.5, 1e-9);
  EXPECT_NEAR(cloud.worldY(0), 2.25, 1e-9);
  EXPECT_NEAR(cloud.worldZ(0), -3, 1e-9);
  EXPECT_EQ(cloud.intensity[1], 0.25f);
  EXPECT_EQ(cloud.colors[1], (Rgba8{40, 50, 60, 255}));
  EXPECT_EQ(scan->as<std::uint16_t>()[1], 0);
  // Scan 1: (x, y, z) -> (100 - y, 200 + x, 10 + z).
  const double expected[3][3] = {{100, 201, 10}, {98, 200, 10.5}, {101, 199, 9}};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(cloud.worldX(2 + k), expected[k][0], 1e-9) << k;
    EXPECT_NEAR(cloud.worldY(2 + k), expected[k][1], 1e-9) << k;
    EXPECT_NEAR(cloud.worldZ(2 + k), expected[k][2], 1e-9) << k;
    EXPECT_EQ(scan->as<std::uint16_t>()[2 + k], 1);
  }
  EXPECT_EQ(cloud.colors[3], (Rgba8{4, 5, 6, 255}));
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[1].columns, 2u);
  EXPECT_EQ(scans[1].rows, 2u);
  EXPECT_EQ(scans[1].position, (std::array<double, 3>{100, 200, 10}));
  EXPECT_EQ(scans[1].points, 3u);
  EXPECT_EQ(scans[1].first_line, 13u);
  EXPECT_EQ(scans[1].transform[12], 100.0);
}

TEST(PtxReader, ChunksEqualTheWholeReadAndTheWriterRoundTrips) {
  test::TempDir dir;
  std::ofstream(dir / "two.ptx") << kTwoScans;
  EXPECT_EQ(detectPointFormat(dir / "two.ptx"), PointFormat("ptx"));
  std::vector<PtxScan> scans;
  const PointCloud whole = readPtx(dir / "two.ptx", {.scans = &scans});
  PtxChunkReader reader(dir / "two.ptx");
  EXPECT_EQ(reader.pointCount(), 5u);
  EXPECT_EQ(reader.scans().size(), 2u);
  PointCloud chunk;
  std::size_t at = 0;
  while (reader.next(chunk, 2)) {
    for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
      EXPECT_EQ(chunk.positions[i], whole.positions[at]);
      EXPECT_EQ(chunk.colors[i], whole.colors[at]);
    }
  }
  EXPECT_EQ(at, 5u);

  writePtx(whole, dir / "back.ptx", {.scans = &scans});
  std::vector<PtxScan> back_scans;
  const PointCloud back = readPtx(dir / "back.ptx", {.scans = &back_scans});
  ASSERT_EQ(back.count, whole.count);
  ASSERT_EQ(back_scans.size(), 2u);
  EXPECT_EQ(back_scans[1].position, scans[1].position);
  for (std::size_t i = 0; i < back.count; ++i) {
    EXPECT_EQ(back.worldX(i), whole.worldX(i));  // shortest round-trip digits
    EXPECT_EQ(back.worldY(i), whole.worldY(i));
    EXPECT_EQ(back.worldZ(i), whole.worldZ(i));
    EXPECT_EQ(back.intensity[i], whole.intensity[i]);
    EXPECT_EQ(back.colors[i], whole.colors[i]);
    EXPECT_EQ(back.scalars[0].as<std::uint16_t>()[i], whole.scalars[0].as<std::uint16_t>()[i]);
  }
  // Through writePointFile, by extension.
  writePointFile(whole, dir / "by_name.ptx");
  EXPECT_EQ(readPointFile(dir / "by_name.ptx").count, 5u);
}

InputErrorInfo ptxError(const std::string& text) {
  try {
    readPtxFromMemory(test::asBytes(text), "t.ptx");
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "t.ptx");
    return e.info();
  }
  ADD_FAILURE() << "no error for " << text;
  return {};
}

TEST(PtxReaderErrors, NameLineScanAndValue) {
  const std::string head = "2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  InputErrorInfo e = ptxError(head + "1 2 3 0.5\n");  // truncated: 1 point line of 2
  EXPECT_EQ(e.line, 12u);
  EXPECT_NE(e.expected.find("1 more point lines of scan 0"), std::string::npos);

  e = ptxError(head + "1 2 x 0.5\n1 2 3 0.5\n");
  EXPECT_EQ(e.line, 11u);
  EXPECT_EQ(e.property, "z");

  e = ptxError(head + "1 2 3 0.5\n1 2 3 0.5 1 2 3\n");
  EXPECT_EQ(e.line, 12u);

  e = ptxError(head + "1 2 3 0.5 1 2 300\n1 2 3 0.5 1 2 3\n");
  EXPECT_EQ(e.property, "blue");

  e = ptxError("2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0\n");
  EXPECT_EQ(e.line, 8u);
  EXPECT_EQ(e.property, "transform row 2");

  e = ptxError("2.5\n1\n");
  EXPECT_EQ(e.property, "columns");
  EXPECT_EQ(e.line, 1u);

  e = ptxError("");
  EXPECT_EQ(e.expected.substr(0, 11), "a PTX scan ");
}

TEST(PtxPdalFiles, CountsAndFirstPoint) {
  const PointCloud color = readPointFile(kPtxData / "ptx/1.2-with-color.ptx");
  EXPECT_EQ(color.count, 1065u);
  ASSERT_TRUE(color.hasColors());
  EXPECT_EQ(color.colors[0], (Rgba8{68, 77, 88, 255}));
  EXPECT_NEAR(color.worldX(0), 637012.24, 1e-6);
  EXPECT_NEAR(color.worldY(0), 849028.31, 1e-6);
  EXPECT_NEAR(color.worldZ(0), 431.66, 1e-6);
  EXPECT_EQ(color.intensity[0], 0.034912f);
  const PointCloud plain = readPointFile(kPtxData / "ptx/no-color.ptx");
  EXPECT_EQ(plain.count, 15u);
  EXPECT_FALSE(plain.hasColors());
}

TEST(PtsReader, CountLinesWithAndWithoutColourAndTheirErrors) {
  const std::string with = "2\n1 2 3 -5 10 20 30\n4 5 6 7 40 50 60\n";
  PointCloud cloud = readPtsFromMemory(test::asBytes(with), "t.pts");
  ASSERT_EQ(cloud.count, 2u);
  EXPECT_EQ(cloud.intensity[0], -5.0f);
  EXPECT_EQ(cloud.colors[1], (Rgba8{40, 50, 60, 255}));
  const std::string without = "1\n1.25 2 3 9\n2\n4 5 6 7\n7 8 9 1\n";  // two scans
  cloud = readPtsFromMemory(test::asBytes(without), "t.pts");
  ASSERT_EQ(cloud.count, 3u);
  EXPECT_FALSE(cloud.hasColors());
  EXPECT_EQ(cloud.worldX(0), 1.25);
  EXPECT_EQ(cloud.intensity[2], 1.0f);

  try {
    readPtsFromMemory(test::asBytes("3\n1 2 3 4\n1 2 3 4\n"), "t.pts");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().line, 1u);
    EXPECT_EQ(e.info().expected, "3 point lines after it");
  }
  try {
    readPtsFromMemory(test::asBytes("1 2 3 4\n"), "t.pts");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().line, 1u);
  }
  try {
    readPtsFromMemory(test::asBytes("2\n1 2 3 4\n1 2 y 4\n"), "t.pts");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().line, 3u);  // the text reader's message
  }
}

TEST(PtsReader, CloudCompareHeaderCommentBeforeTheCount) {
  // CloudCompare 2.11's "-C_EXPORT_FMT ASC -EXT pts -ADD_HEADER -ADD_PTS_COUNT": the column names
  // as a comment, then the count. The count check took the comment for a point line before any
  // count and refused the file; the text reader takes it for the names.
  const std::string text =
      "//X Y Z R G B intensity Nx Ny Nz\n2\n"
      "889.796875000 250.187500000 468.359375000 112 154 114 225.625000000 0.308109 0.142517 "
      "-0.940615\n"
      "794.421875000 156.578125000 651.359375000 163 140 173 116.812500000 -0.051091 -0.868550 "
      "-0.492961\n";
  const PointCloud cloud = readPtsFromMemory(test::asBytes(text), "cc.pts");
  ASSERT_EQ(cloud.count, 2u);
  EXPECT_EQ(cloud.worldX(0), 889.796875);
  EXPECT_EQ(cloud.colors[1], (Rgba8{163, 140, 173, 255}));
  EXPECT_EQ(cloud.intensity[0], 225.625f);
  EXPECT_EQ(cloud.normals[1], (Float3{-0.051091f, -0.868550f, -0.492961f}));
  // A comment among the points is not counted as one.
  EXPECT_EQ(readPtsFromMemory(test::asBytes("1\n# scan 1\n1 2 3 4\n"), "t.pts").count, 1u);
}

TEST(PtsPdalFiles, TestPtsValuesAndAWrittenPtsReadsBack) {
  test::TempDir dir;
  const PointCloud cloud = readPointFile(kPtxData / "pts/test.pts");
  EXPECT_EQ(detectPointFormat(kPtxData / "pts/test.pts"), PointFormat("pts"));
  ASSERT_EQ(cloud.count, 19u);
  EXPECT_EQ(cloud.worldX(0), 3.980972);
  EXPECT_EQ(cloud.worldY(0), -2.006119);
  EXPECT_EQ(cloud.worldZ(0), -0.010086);
  EXPECT_EQ(cloud.colors[0], (Rgba8{97, 59, 38, 255}));
  writePointFile(cloud, dir / "back.pts");
  const PointCloud back = readPointFile(dir / "back.pts");
  ASSERT_EQ(back.count, 19u);
  for (std::size_t i = 0; i < back.count; ++i) {
    EXPECT_EQ(back.worldX(i), cloud.worldX(i));
    EXPECT_EQ(back.colors[i], cloud.colors[i]);
    EXPECT_EQ(back.intensity[i], cloud.intensity[i]);
  }
  EXPECT_EQ(readPointFile(kPtxData / "pts/autzen.pts").count, 10u);
}

}  // namespace
}  // namespace parallax
