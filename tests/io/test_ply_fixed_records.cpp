// Fixed-size binary records: a local file's records are read by blocks of whole records (pread)
// and the runs of adjacent properties (x y z, nx ny nz, red green blue alpha) are decoded a
// record at a time; every path must give what the property-by-property loops give, bit for bit,
// wherever a block, a range or a chunk ends.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/ply_reader.h"
#include "io/ply_test_files.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::catchInputError;
using test::CaughtInputError;
using test::expectMessageHas;
using test::expectSamePoints;
using test::PlyBody;
using test::plyHeader;

// The reader's block (ply_reader.cpp kReadBlockBytes): 128 KiB of whole records.
constexpr std::size_t kReadBlockBytes = 128 << 10;

// Not a multiple of the block for any record size below, and more than one range (512 KiB) of
// input, so that blocks end inside ranges and ranges end inside blocks' worth of records.
constexpr std::size_t kCount = 40'000;

struct FixedRecord {
  float x, y, z, nx, ny, nz;
  std::uint8_t red, green, blue, alpha;
};

FixedRecord fixedRecord(std::size_t i) {
  // Floats exactly representable, UTM-sized eastings, a negative zero among the normals.
  FixedRecord r;
  r.x = 512000.25f + float(i) * 0.5f;
  r.y = -1000.125f + float(i % 997) * 0.25f;
  r.z = 10.5f - float(i % 61) * 0.125f;
  r.nx = float(i % 7) / 8.0f - 0.5f;
  r.ny = i % 5 == 0 ? -0.0f : float(i % 11) / 16.0f;
  r.nz = -float(i % 13) / 32.0f;
  r.red = std::uint8_t(i), r.green = std::uint8_t(i >> 8), r.blue = std::uint8_t(i * 7);
  r.alpha = std::uint8_t(255 - i % 256);
  return r;
}

// A vertex element of `kCount` fixedRecord()s with the properties in `order` (names of
// FixedRecord's fields; floats and uchars), in `format`.
std::string fixedRecordFile(PlyFormat format, const std::vector<std::string_view>& order) {
  std::string lines = "element vertex " + std::to_string(kCount) + "\n";
  for (std::string_view name : order) {
    const bool color = name == "red" || name == "green" || name == "blue" || name == "alpha";
    lines += std::string("property ") + (color ? "uchar " : "float ") + std::string(name) + "\n";
  }
  std::string header = plyHeader(format, {});
  header.insert(header.find("end_header"), lines);
  PlyBody body(format);
  for (std::size_t i = 0; i < kCount; ++i) {
    const FixedRecord r = fixedRecord(i);
    for (std::string_view name : order) {
      if (name == "x") body.put(r.x);
      if (name == "y") body.put(r.y);
      if (name == "z") body.put(r.z);
      if (name == "nx") body.put(r.nx);
      if (name == "ny") body.put(r.ny);
      if (name == "nz") body.put(r.nz);
      if (name == "red") body.put(r.red);
      if (name == "green") body.put(r.green);
      if (name == "blue") body.put(r.blue);
      if (name == "alpha") body.put(r.alpha);
    }
    body.end();
  }
  return header + body.bytes();
}

void expectFixedRecordValues(const PointCloud& cloud, bool with_alpha) {
  ASSERT_EQ(cloud.count, kCount);
  ASSERT_EQ(cloud.normals.size(), kCount);
  ASSERT_EQ(cloud.colors.size(), kCount);
  for (std::size_t i = 0; i < kCount; ++i) {
    const FixedRecord r = fixedRecord(i);
    ASSERT_EQ(cloud.worldX(i), double(r.x)) << "point " << i;
    ASSERT_EQ(cloud.worldY(i), double(r.y)) << "point " << i;
    ASSERT_EQ(cloud.worldZ(i), double(r.z)) << "point " << i;
    const Float3 normal = cloud.normals[i];
    // Bits, not values: -0.0f must stay negative.
    ASSERT_EQ(std::memcmp(&normal, &r.nx, sizeof normal), 0) << "normal of point " << i;
    ASSERT_EQ(cloud.colors[i],
              (Rgba8{r.red, r.green, r.blue, std::uint8_t(with_alpha ? r.alpha : 255)}))
        << "point " << i;
  }
}

void expectSameQuantizationAndBounds(const PointCloud& a, const PointCloud& b) {
  EXPECT_EQ(a.quantization, b.quantization);
  EXPECT_EQ(a.bounds, b.bounds);
}

TEST(PlyFixedRecords, AdjacentRunsDecodeAsThePropertyLoopsDo) {
  test::TempDir dir;
  const std::vector<std::string_view> adjacent = {"x",  "y",   "z",     "nx",   "ny",
                                                  "nz", "red", "green", "blue", "alpha"};
  const std::vector<std::string_view> scattered = {"red", "x", "nx",   "green", "y",
                                                   "ny",  "z", "blue", "nz",    "alpha"};
  // Little endian, runs adjacent: the record-at-a-time copies; scattered, or big endian (bytes
  // swapped): one loop a property.
  const PointCloud runs =
      readPly(dir.write("runs.ply", fixedRecordFile(PlyFormat::BinaryLittleEndian, adjacent)));
  const PointCloud apart =
      readPly(dir.write("apart.ply", fixedRecordFile(PlyFormat::BinaryLittleEndian, scattered)));
  const PointCloud swapped =
      readPly(dir.write("swapped.ply", fixedRecordFile(PlyFormat::BinaryBigEndian, adjacent)));
  expectFixedRecordValues(runs, /*with_alpha=*/true);
  expectFixedRecordValues(apart, /*with_alpha=*/true);
  expectSamePoints(runs, apart);
  expectSamePoints(runs, swapped);
  expectSameQuantizationAndBounds(runs, apart);
  expectSameQuantizationAndBounds(runs, swapped);
  EXPECT_EQ(runs.bounds.min[0], double(fixedRecord(0).x));
  EXPECT_EQ(runs.bounds.max[0], double(fixedRecord(kCount - 1).x));
}

TEST(PlyFixedRecords, ColoursWithoutAlphaOrWithAlphaElsewhere) {
  test::TempDir dir;
  // 27-byte records: 4854 a block, and a range of 19418 records ends 2 records into a block.
  const PointCloud opaque = readPly(dir.write(
      "opaque.ply", fixedRecordFile(PlyFormat::BinaryLittleEndian,
                                    {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"})));
  expectFixedRecordValues(opaque, /*with_alpha=*/false);
  const PointCloud alpha_first = readPly(dir.write(
      "alpha_first.ply",
      fixedRecordFile(PlyFormat::BinaryLittleEndian,
                      {"alpha", "x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"})));
  expectFixedRecordValues(alpha_first, /*with_alpha=*/true);
}

TEST(PlyFixedRecords, AdjacentDoublePositionsDecodeAsSwappedOnes) {
  test::TempDir dir;
  std::vector<test::World> points;
  for (std::size_t i = 0; i < 20'011; ++i) {
    points.push_back(
        {4.5e6 + double(i) * 0.001953125, -123.0 - double(i % 101) * 0.5, double(i % 17) * 1024.0});
  }
  const PointCloud native = readPly(
      dir.write("native.ply", test::positionFile(PlyFormat::BinaryLittleEndian, "double", points)));
  const PointCloud swapped = readPly(
      dir.write("swapped.ply", test::positionFile(PlyFormat::BinaryBigEndian, "double", points)));
  EXPECT_EQ(test::worldPositions(native), points);
  expectSamePoints(native, swapped);
  expectSameQuantizationAndBounds(native, swapped);
}

// The positions run reads x, y and z only: a NaN or an infinity in the property after z is a
// value of that property, not a coordinate, and stays out of the bounds.
TEST(PlyFixedRecords, ANonFiniteValueAfterZIsNoCoordinate) {
  std::string file = plyHeader(PlyFormat::BinaryLittleEndian,
                               {"element vertex 3", "property float x", "property float y",
                                "property float z", "property float w"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  body.put(1.0f).put(2.0f).put(3.0f).put(nan).end();
  body.put(4.0f).put(5.0f).put(6.0f).put(inf).end();
  body.put(7.0f).put(8.0f).put(9.0f).put(-inf).end();
  file += body.bytes();
  auto expect_w_apart = [&](const PointCloud& cloud) {
    ASSERT_EQ(cloud.count, 3u);
    EXPECT_EQ(cloud.bounds.min, (std::array<double, 3>{1.0, 2.0, 3.0}));
    EXPECT_EQ(cloud.bounds.max, (std::array<double, 3>{7.0, 8.0, 9.0}));
    const ScalarColumn* w = cloud.findScalar("w");
    ASSERT_NE(w, nullptr);
    EXPECT_TRUE(std::isnan(w->as<float>()[0]));
    EXPECT_EQ(w->as<float>()[1], inf);
    EXPECT_EQ(w->as<float>()[2], -inf);
  };
  test::TempDir dir;
  expect_w_apart(readPly(dir.write("w.ply", file)));  // by blocks
  expect_w_apart(readPlyFromMemory(asBytes(file), "w.ply"));
}

// A non-finite coordinate in the last record of a block, and in the last record of the file, is
// reported with its record and the file's byte offset (not the buffer's).
TEST(PlyFixedRecords, ANonFiniteCoordinateAtABlocksEndIsReportedWhereItIs) {
  constexpr std::size_t kRecord = 12;  // float x y z
  constexpr std::size_t kPerBlock = kReadBlockBytes / kRecord;
  constexpr std::size_t kBadFilePoints = 2 * kPerBlock + 5;
  const std::string header = plyHeader(
      PlyFormat::BinaryLittleEndian, {"element vertex " + std::to_string(kBadFilePoints),
                                      "property float x", "property float y", "property float z"});
  struct Bad {
    std::size_t record;
    int axis;
    float value;
    const char* property;
  };
  const float inf = std::numeric_limits<float>::infinity();
  for (const Bad bad :
       {Bad{kPerBlock - 1, 2, inf, "'z'"}, Bad{kPerBlock, 0, -inf, "'x'"},
        Bad{kBadFilePoints - 1, 1, std::numeric_limits<float>::quiet_NaN(), "'y'"}}) {
    SCOPED_TRACE("record " + std::to_string(bad.record));
    PlyBody body(PlyFormat::BinaryLittleEndian);
    for (std::size_t i = 0; i < kBadFilePoints; ++i) {
      float xyz[3] = {float(i), 1.0f, 2.0f};
      if (i == bad.record) xyz[bad.axis] = bad.value;
      body.put(xyz[0]).put(xyz[1]).put(xyz[2]).end();
    }
    test::TempDir dir;
    const auto path = dir.write("bad.ply", header + body.bytes());
    const std::size_t offset = header.size() + bad.record * kRecord + std::size_t(bad.axis) * 4;
    CaughtInputError caught = catchInputError([&] { readPly(path); });
    expectMessageHas(caught, {"bad.ply", bad.property, "record " + std::to_string(bad.record),
                              "byte offset " + std::to_string(offset)});
  }
}

// PlyChunkReader reads fixed-size records by blocks as readPly does: chunks that end inside a
// block, on a block's end and past a range's end give readPly's points, every column.
TEST(PlyFixedRecords, ChunksOfEverySizeEqualReadPly) {
  test::TempDir dir;
  const auto path = dir.write(
      "chunks.ply", fixedRecordFile(PlyFormat::BinaryLittleEndian,
                                    {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"}));
  const PointCloud whole = readPly(path);
  constexpr std::size_t kPerBlock = kReadBlockBytes / 27;
  for (std::size_t max_points :
       {kPerBlock - 1, kPerBlock, kPerBlock + 1, 4 * kPerBlock + 3, kCount}) {
    SCOPED_TRACE("chunks of " + std::to_string(max_points));
    PlyChunkReader reader(path);
    reader.setQuantization(whole.quantization);
    PointCloud chunk;
    std::size_t index = 0;
    while (reader.next(chunk, max_points)) {
      ASSERT_LE(chunk.count, max_points);
      for (std::size_t i = 0; i < chunk.count; ++i, ++index) {
        ASSERT_EQ(chunk.positions[i], whole.positions[index]) << "point " << index;
        ASSERT_EQ(chunk.normals[i], whole.normals[index]) << "point " << index;
        ASSERT_EQ(chunk.colors[i], whole.colors[index]) << "point " << index;
      }
    }
    EXPECT_EQ(index, kCount);
  }
}

}  // namespace
}  // namespace parallax
