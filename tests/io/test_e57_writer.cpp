// E57 writing, read back by Parallax: a generated file of several spherical and cartesian scans
// with poses, invalid points, 16-bit colour and integer intensity, compared with values computed
// here from the generating formulas; and a cloud written as one scan, read back exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "io/e57/e57_reader.h"
#include "io/e57/e57_test_files.h"
#include "io/e57/e57_writer.h"
#include "io/point_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

// Record i of scan s, in the scan's own frame: a spiral of ranges and angles.
struct Record {
  double range, azimuth, elevation;
  int invalid;           // 0 valid, 1 direction only, 2 nothing
  int intensity;         // 0..4095
  int red, green, blue;  // 0..65535
  int row;
};

Record record(int s, std::uint64_t i) {
  Record r;
  r.range = 1.0 + 0.001 * double((i * 37 + std::uint64_t(s) * 11) % 5000);  // 1 mm steps
  r.azimuth = -std::numbers::pi + 0.0007 * double(i % 8000);
  r.elevation = -1.2 + 0.0003 * double((i * 7) % 8000);
  r.invalid = i % 13 == 5 ? 2 : (i % 17 == 3 ? 1 : 0);
  r.intensity = int((i * 131) % 4096);
  r.red = int((i * 257) % 65536), r.green = int((i * 511) % 65536), r.blue = 65535 - r.red;
  r.row = int(i / 100);
  return r;
}

constexpr int kScans = 3;
constexpr std::uint64_t kRecords[kScans] = {5000, 7777, 300};
// Scan s is turned by s * 30 degrees about z and moved to (10 s, -5 s, 1.5).
double turn(int s) {
  return double(s) * std::numbers::pi / 6.0;
}
std::array<double, 3> place(int s) {
  return {10.0 * s, -5.0 * s, 1.5};
}

E57ScanSource makeScan(int s) {
  E57ScanSource scan;
  scan.name = "scan " + std::to_string(s);
  scan.record_count = kRecords[s];
  scan.pose.rotation = {std::cos(turn(s) / 2), 0.0, 0.0, std::sin(turn(s) / 2)};
  scan.pose.translation = place(s);
  const bool cartesian = s == 2;  // the last scan in cartesian single floats
  auto add = [&](const char* name, E57Field::Kind kind, std::int64_t lo, std::int64_t hi,
                 double scale = 1.0) {
    E57Field f;
    f.name = name, f.kind = kind, f.minimum = lo, f.maximum = hi, f.scale = scale;
    scan.fields.push_back(f);
  };
  if (cartesian) {
    for (const char* name : {"cartesianX", "cartesianY", "cartesianZ"}) {
      E57Field f;
      f.name = name, f.kind = E57Field::Kind::Float, f.single_precision = true;
      scan.fields.push_back(f);
    }
    add("cartesianInvalidState", E57Field::Kind::Integer, 0, 2);
  } else {
    add("sphericalRange", E57Field::Kind::ScaledInteger, 0, 10'000'000, 0.001);
    E57Field az;
    az.name = "sphericalAzimuth", az.kind = E57Field::Kind::Float;
    scan.fields.push_back(az);
    az.name = "sphericalElevation";
    scan.fields.push_back(az);
    add("sphericalInvalidState", E57Field::Kind::Integer, 0, 2);
    scan.range_maximum = 10.0;
  }
  add("intensity", E57Field::Kind::Integer, 0, 4095);
  add("colorRed", E57Field::Kind::Integer, 0, 65535);
  add("colorGreen", E57Field::Kind::Integer, 0, 65535);
  add("colorBlue", E57Field::Kind::Integer, 0, 65535);
  add("rowIndex", E57Field::Kind::Integer, 0, 1000);
  scan.intensity_limits = std::array<double, 2>{0.0, 4095.0};
  scan.color_limits = std::array<double, 6>{0, 65535, 0, 65535, 0, 65535};
  if (cartesian) {
    Bounds3 b;
    b.extend(-11, -11, -11), b.extend(11, 11, 11);
    scan.cartesian_bounds = b;
  }
  scan.fill = [s, cartesian](std::uint64_t first, std::size_t count,
                             std::vector<std::vector<double>>& values) {
    for (std::size_t k = 0; k < count; ++k) {
      const Record r = record(s, first + k);
      if (cartesian) {
        values[0][k] = r.range * std::cos(r.elevation) * std::cos(r.azimuth);
        values[1][k] = r.range * std::cos(r.elevation) * std::sin(r.azimuth);
        values[2][k] = r.range * std::sin(r.elevation);
      } else {
        values[0][k] = r.range, values[1][k] = r.azimuth, values[2][k] = r.elevation;
      }
      values[3][k] = r.invalid;
      values[4][k] = r.intensity;
      values[5][k] = r.red, values[6][k] = r.green, values[7][k] = r.blue;
      values[8][k] = r.row;
    }
  };
  return scan;
}

struct Point {
  int scan;
  double x, y, z;
  Record r;
};

// The valid points in the file's frame, computed from the formulas (rotation about z written
// out, not through a quaternion).
std::vector<Point> expectedPoints() {
  std::vector<Point> points;
  for (int s = 0; s < kScans; ++s) {
    for (std::uint64_t i = 0; i < kRecords[s]; ++i) {
      const Record r = record(s, i);
      if (r.invalid != 0) continue;
      double x = r.range * std::cos(r.elevation) * std::cos(r.azimuth);
      double y = r.range * std::cos(r.elevation) * std::sin(r.azimuth);
      double z = r.range * std::sin(r.elevation);
      if (s == 2) x = double(float(x)), y = double(float(y)), z = double(float(z));
      const double c = std::cos(turn(s)), sn = std::sin(turn(s));
      points.push_back(
          {s, c * x - sn * y + place(s)[0], sn * x + c * y + place(s)[1], z + place(s)[2], r});
    }
  }
  return points;
}

void expectGenerated(const PointCloud& cloud, std::size_t first, const std::vector<Point>& all) {
  const ScalarColumn* scan = cloud.findScalar(column_names::kScanIndex);
  const ScalarColumn* row = cloud.findScalar("rowIndex");
  ASSERT_NE(scan, nullptr);
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->type, ScalarType::Int32);
  const double tolerance = 1e-6;  // 1 mm range steps stored exactly; float32 azimuths
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const Point& e = all[first + i];
    ASSERT_EQ(scan->as<std::uint32_t>()[i], std::uint32_t(e.scan)) << "point " << first + i;
    ASSERT_NEAR(cloud.worldX(i), e.x, tolerance) << "point " << first + i;
    ASSERT_NEAR(cloud.worldY(i), e.y, tolerance) << "point " << first + i;
    ASSERT_NEAR(cloud.worldZ(i), e.z, tolerance) << "point " << first + i;
    const auto to8 = [](int v) { return std::uint8_t(std::lround(v * 255.0 / 65535.0)); };
    ASSERT_EQ(cloud.colors[i], (Rgba8{to8(e.r.red), to8(e.r.green), to8(e.r.blue), 255}));
    ASSERT_FLOAT_EQ(cloud.intensity[i], float(e.r.intensity * 65535.0 / 4095.0));
    ASSERT_EQ(row->as<std::int32_t>()[i], e.r.row);
  }
}

TEST(E57Writer, SeveralSphericalScansWithPosesRoundTrip) {
  test::TempDir dir;
  std::vector<E57ScanSource> scans;
  for (int s = 0; s < kScans; ++s) scans.push_back(makeScan(s));
  const auto path = dir / "scans.e57";
  writeE57Scans(scans, path);
  const std::string bytes = test::readBytes(path);
  ASSERT_EQ(bytes.size() % 1024, 0u);
  for (std::size_t page = 0; page < bytes.size(); page += 1024) {
    std::string sealed = bytes.substr(page, 1024);
    test::resealPages(sealed);
    ASSERT_EQ(sealed, bytes.substr(page, 1024)) << "checksum of page " << page / 1024;
  }
  const std::vector<Point> expected = expectedPoints();
  const PointCloud cloud = readE57(path);
  ASSERT_EQ(cloud.count, expected.size());
  expectGenerated(cloud, 0, expected);
  EXPECT_EQ(cloud.source.color, ScalarType::UInt16);

  // Streamed in chunks of an odd size, across scans and packets: the same points.
  E57ChunkReader reader(path);
  EXPECT_EQ(reader.pointCount(), kRecords[0] + kRecords[1] + kRecords[2]);
  ASSERT_EQ(reader.header().document.scans.size(), std::size_t(kScans));
  EXPECT_EQ(reader.header().document.scans[1].pose.translation, place(1));
  PointCloud chunk;
  std::size_t at = 0;
  while (reader.next(chunk, 997)) {
    expectGenerated(chunk, at, expected);
    at += chunk.count;
  }
  EXPECT_EQ(at, expected.size());
}

PointCloud smallCloud() {
  PointCloud cloud;
  cloud.count = 1000;
  cloud.quantization.scale = {0.001, 0.002, 0.0005};
  cloud.quantization.offset = {500000.0, 4200000.0, 100.0};
  cloud.positions = Column<Int3>(cloud.count);
  cloud.colors = Column<Rgba8>(cloud.count);
  cloud.intensity = Column<float>(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const auto k = std::int32_t(i);
    cloud.positions[i] = {k * 997 - 400000, -k * 13, (k * k) % 70001};
    cloud.colors[i] = {std::uint8_t(i), std::uint8_t(255 - i % 256), std::uint8_t(i * 7), 255};
    cloud.intensity[i] = float((i * 61) % 65536);
  }
  cloud.computeBounds();
  return cloud;
}

void expectSameCloud(const PointCloud& read, const PointCloud& cloud) {
  ASSERT_EQ(read.count, cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    // UTM-sized coordinates: the reader's own quantization holds them to well under 1e-6.
    ASSERT_NEAR(read.worldX(i), cloud.worldX(i), 1e-6) << i;
    ASSERT_NEAR(read.worldY(i), cloud.worldY(i), 1e-6) << i;
    ASSERT_NEAR(read.worldZ(i), cloud.worldZ(i), 1e-6) << i;
    ASSERT_EQ(read.colors[i], cloud.colors[i]) << i;
    ASSERT_EQ(read.intensity[i], cloud.intensity[i]) << i;
  }
}

TEST(E57Writer, CloudRoundTripsAsScaledIntegersAndAsDoubles) {
  test::TempDir dir;
  const PointCloud cloud = smallCloud();
  writePointFile(cloud, dir / "scaled.e57");
  expectSameCloud(readPointFile(dir / "scaled.e57"), cloud);
  writeE57(cloud, dir / "doubles.e57", {.scaled_integer_positions = false});
  expectSameCloud(readE57(dir / "doubles.e57"), cloud);
  // Scaled integers take the cloud's own grid: fewer bytes than doubles.
  EXPECT_LT(std::filesystem::file_size(dir / "scaled.e57"),
            std::filesystem::file_size(dir / "doubles.e57"));
  // Read back with the written quantization, the integers are the cloud's own.
  E57ChunkReader reader(dir / "scaled.e57");
  reader.setQuantization(cloud.quantization);
  PointCloud again;
  ASSERT_TRUE(reader.next(again, 5000));
  for (std::size_t i = 0; i < cloud.count; ++i) ASSERT_EQ(again.positions[i], cloud.positions[i]);
}

TEST(E57Writer, ConvertReportsWhatE57Drops) {
  PointCloud cloud = smallCloud();
  cloud.normals = Column<Float3>(cloud.count);
  const auto losses = describeWriteLosses(cloud, "out.e57");
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_NE(losses[0].find("normals"), std::string::npos);
}

// A_B.e57's two scans are written as one: the report says so (it kept quiet, scan_index left out
// of the report whatever its values); one scan's cloud loses nothing.
TEST(E57Writer, ConvertReportsScansJoinedIntoOne) {
  const PointCloud two = readPointFile(test::e57DataFile("A_B.e57"));
  EXPECT_EQ(
      describeWriteLosses(two, "out.e57"),
      (std::vector<std::string>{"scan_index (the points of scans 0 to 1 written as one scan)"}));
  EXPECT_TRUE(describeWriteLosses(readPointFile(test::e57DataFile("A4.e57")), "out.e57").empty());
}

}  // namespace
}  // namespace parallax
