// Round trips: LAS -> LAS, LAS -> PLY -> LAS, text -> LAS, keeping values exactly.
#include "io/las_writer.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <memory>

#include "core/byte_order.h"
#include "core/point_gather.h"
#include "io/las_header.h"
#include "io/las_reader.h"
#include "io/ply_reader.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "io/test_las_builder.h"
#include "io/text_reader.h"
#include "support/allocation_counter.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::fileBytes;

using test::LasTestFile;
using test::LasTestPoint;

LasTestFile manyPoints(int minor, int format) {
  LasTestFile file{.minor = minor, .format = format};
  file.scale[0] = 0.001, file.scale[1] = 0.001, file.scale[2] = 0.01;
  file.offset[0] = 512000.0, file.offset[1] = 5400000.0, file.offset[2] = 0.0;
  const bool ext = format >= 6;
  for (int i = 0; i < 5000; ++i) {
    LasTestPoint p;
    // A 1 km tile at millimetres, as real LiDAR tiles are.
    p.x = (i * 7919) % 1000000 - 500000, p.y = -((i * 104729) % 1000000), p.z = i % 1000;
    p.intensity = std::uint16_t(i * 13);
    p.return_number = std::uint8_t(1 + i % (ext ? 15 : 7));
    p.number_of_returns = ext ? 15 : 7;
    p.scan_direction = i & 1, p.edge = (i >> 1) & 1;
    p.classification = std::uint8_t(ext ? i % 256 : i % 32);
    p.flags = std::uint8_t(ext ? i % 16 : i % 8);
    p.channel = ext ? std::uint8_t(i % 4) : 0;
    p.scan_angle = std::int16_t(ext ? i * 3 - 7000 : i % 180 - 90);
    p.user_data = std::uint8_t(i * 3), p.point_source_id = std::uint16_t(i * 11);
    p.gps_time = 1e8 + i * 0.000123;
    // Colours that are exact in the 8-bit model: c * 257.
    p.red = std::uint16_t((i % 256) * 257), p.green = std::uint16_t(((i * 7) % 256) * 257);
    p.blue = std::uint16_t(((i * 13) % 256) * 257), p.nir = std::uint16_t(i * 5);
    file.points.push_back(p);
  }
  return file;
}

void expectSameCloud(const PointCloud& a, const PointCloud& b, bool same_scalar_types = true) {
  ASSERT_EQ(a.count, b.count);
  EXPECT_EQ(a.quantization, b.quantization);
  for (std::size_t i = 0; i < a.count; ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << i;
  ASSERT_EQ(a.hasColors(), b.hasColors());
  for (std::size_t i = 0; i < a.colors.size(); ++i) ASSERT_EQ(a.colors[i], b.colors[i]) << i;
  ASSERT_EQ(a.hasIntensity(), b.hasIntensity());
  for (std::size_t i = 0; i < a.intensity.size(); ++i) ASSERT_EQ(a.intensity[i], b.intensity[i]);
  ASSERT_EQ(a.hasClassification(), b.hasClassification());
  for (std::size_t i = 0; i < a.classification.size(); ++i) {
    ASSERT_EQ(a.classification[i], b.classification[i]);
  }
  for (const ScalarColumn& column : a.scalars) {
    const ScalarColumn* other = b.findScalar(column.name);
    ASSERT_NE(other, nullptr) << column.name;
    if (same_scalar_types) {
      EXPECT_EQ(column.type, other->type) << column.name;
    }
    for (std::size_t i = 0; i < a.count; ++i) {
      ASSERT_EQ(column.valueAsDouble(i), other->valueAsDouble(i)) << column.name << " " << i;
    }
  }
}

TEST(LasWriter, EveryFormatSurvivesLasToLas) {
  test::TempDir dir;
  for (auto [minor, format] : {std::pair{2, 0}, {2, 1}, {2, 2}, {2, 3}, {4, 6}, {4, 7}, {4, 8}}) {
    SCOPED_TRACE("format " + std::to_string(format));
    PointCloud source = readLasFromMemory(asBytes(test::makeLas(manyPoints(minor, format))), "in");
    LasWritePlan plan = planLasWrite(source);
    EXPECT_EQ(plan.minor_version, minor);
    EXPECT_EQ(plan.point_format, format);
    EXPECT_TRUE(plan.extra_bytes.empty());
    EXPECT_TRUE(plan.losses.empty());
    auto path = dir / "out.las";
    writeLas(source, path);
    expectSameCloud(source, readLas(path));
    LasHeader header = readLasHeader(path);
    EXPECT_EQ(header.point_count, 5000u);
    EXPECT_EQ(header.bounds, source.bounds);
  }
}

TEST(LasWriter, WaveformFormatsKeepTheirFieldsAsExtraBytes) {
  test::TempDir dir;
  PointCloud source = readLasFromMemory(asBytes(test::makeLas(manyPoints(4, 10))), "in");
  auto path = dir / "out.las";
  writeLas(source, path);
  PointCloud back = readLas(path);
  EXPECT_EQ(readLasHeader(path).point_format, 8);
  expectSameCloud(source, back);
}

TEST(LasWriter, NormalsAndOtherScalarsBecomeExtraBytes) {
  test::TempDir dir;
  PointCloud cloud;
  cloud.count = 3;
  cloud.positions = Column<Int3>(3);
  cloud.normals = Column<Float3>(3);
  for (int i = 0; i < 3; ++i) {
    cloud.positions[std::size_t(i)] = {i, 2 * i, 3 * i};
    cloud.normals[std::size_t(i)] = {0.5f * float(i), -1.0f, 0.25f};
  }
  ScalarColumn confidence{"confidence", ScalarType::UInt16, ByteBuffer(6)};
  for (int i = 0; i < 3; ++i) confidence.as<std::uint16_t>()[i] = std::uint16_t(1000 + i);
  cloud.scalars.push_back(std::move(confidence));
  ScalarColumn returns{"ReturnNumber", ScalarType::Float32, ByteBuffer(12)};  // PDAL's name
  for (int i = 0; i < 3; ++i) returns.as<float>()[i] = float(i + 1);
  cloud.scalars.push_back(std::move(returns));
  cloud.computeBounds();
  auto path = dir / "extra.las";
  writeLas(cloud, path);
  LasHeader header = readLasHeader(path);
  EXPECT_EQ(header.versionString(), "1.2");
  ASSERT_EQ(header.extra_bytes.size(), 4u);
  // The normals as CloudCompare and PDAL write them, which they read back as normals: float
  // extra bytes (data type 9) named NormalX NormalY NormalZ, first.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(header.extra_bytes[std::size_t(axis)].name, kLasNormalExtraBytesNames[axis]);
    EXPECT_EQ(header.extra_bytes[std::size_t(axis)].data_type, 9);
    EXPECT_EQ(header.extra_bytes[std::size_t(axis)].record_offset, std::size_t(20 + 4 * axis));
  }
  EXPECT_EQ(header.extra_bytes[3].name, "confidence");
  PointCloud back = readLas(path);
  ASSERT_TRUE(back.hasNormals());
  EXPECT_EQ(back.findScalar("NormalX"), nullptr);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(back.normals[i], cloud.normals[i]) << i;
  EXPECT_EQ(back.findScalar("confidence")->as<std::uint16_t>()[1], 1001);
  EXPECT_EQ(back.findScalar("return_number")->as<std::uint8_t>()[2], 3);
  EXPECT_EQ(back.positions[2], (Int3{2, 4, 6}));
}

// A LAS file whose normals are double extra bytes of its own names, between other extra bytes:
// read as normals, written back (convert keeps the source's layout) at the same places in the
// same type, so the records are the same bytes.
TEST(LasWriter, ASourcesNormalExtraBytesAreWrittenBackInPlace) {
  test::TempDir dir;
  test::LasTestFile file{.minor = 4, .format = 6, .extra_bytes = 2 + 24 + 1};
  file.vlrs.push_back(
      {"LASF_Spec", 4,
       test::extraBytesDescriptor(3, "amplitude") + test::extraBytesDescriptor(10, "nx") +
           test::extraBytesDescriptor(10, "ny") + test::extraBytesDescriptor(10, "nz") +
           test::extraBytesDescriptor(1, "flag")});
  for (int i = 0; i < 3; ++i) {
    test::LasTestPoint p;
    p.x = i, p.y = 10 * i, p.z = -i;
    std::string extra(27, '\0');
    test::putAt(extra, 0, std::uint16_t(100 + i));
    test::putAt(extra, 2, 0.5 * i);
    test::putAt(extra, 10, -0.25);
    test::putAt(extra, 18, 0.75 - i);
    extra[26] = char(7 + i);
    p.extra.assign(extra.begin(), extra.end());
    file.points.push_back(p);
  }
  const std::string bytes = test::makeLas(file);
  const auto in = dir / "in.las";
  { std::ofstream(in, std::ios::binary) << bytes; }
  PointCloud cloud = readLas(in);
  ASSERT_TRUE(cloud.hasNormals());
  EXPECT_EQ(cloud.normals[2], (Float3{1.0f, -0.25f, -1.25f}));
  LasWriteOptions options;
  options.source = std::make_shared<LasHeader>(readLasHeaderWithRecords(in));
  const auto out = dir / "out.las";
  const LasWritePlan plan = planLasWrite(cloud, options);
  EXPECT_TRUE(plan.losses.empty()) << plan.losses.front();
  writeLas(cloud, out, options);
  const LasHeader source = readLasHeader(in), written = readLasHeader(out);
  ASSERT_EQ(written.extra_bytes.size(), 5u);
  EXPECT_EQ(written.extra_bytes[1].name, "nx");
  EXPECT_EQ(written.extra_bytes[3].data_type, 10);
  EXPECT_EQ(written.record_length, source.record_length);
  const std::string got = test::fileBytes(out);
  const std::size_t records = std::size_t(source.record_length) * 3;
  ASSERT_EQ(got.size(), written.point_data_offset + records);
  EXPECT_EQ(got.substr(written.point_data_offset), bytes.substr(source.point_data_offset, records));
}

TEST(LasWriter, ChoosesLas14WhenTheValuesNeedIt) {
  PointCloud cloud;
  cloud.count = 1;
  cloud.positions = Column<Int3>(1);
  cloud.positions[0] = {0, 0, 0};
  cloud.classification = Column<std::uint8_t>(1);
  cloud.classification[0] = 40;
  EXPECT_EQ(planLasWrite(cloud).minor_version, 4);
  EXPECT_EQ(planLasWrite(cloud).point_format, 6);
  LasWritePlan forced = planLasWrite(cloud, {.minor_version = 2});
  EXPECT_EQ(forced.point_format, 0);
  EXPECT_FALSE(forced.losses.empty());
}

TEST(LasWriter, EmptyCloudWritesAValidFile) {
  test::TempDir dir;
  PointCloud empty;
  auto path = dir / "empty.las";
  writeLas(empty, path);
  EXPECT_EQ(readLas(path).count, 0u);
  EXPECT_EQ(readLasHeader(path).point_format, 0);
}

// The point records of a LAS file in memory (header offsets of LAS 1.4 R15 Table 3).
std::string recordsOf(const std::string& las) {
  std::uint32_t offset = 0, legacy = 0;
  std::uint16_t length = 0;
  std::uint64_t count = 0;
  std::memcpy(&offset, las.data() + 96, 4);
  std::memcpy(&length, las.data() + 105, 2);
  std::memcpy(&legacy, las.data() + 107, 4);
  count = legacy;
  if (las[25] >= 4 && legacy == 0) std::memcpy(&count, las.data() + 247, 8);
  return las.substr(offset, std::size_t(count) * length);
}

// The stream writer, fed in uneven batches (one point, across LAZ chunk borders, the rest), writes
// the bytes writeLas writes for the whole cloud: LAS and LAZ, a 1.2 and a 1.4 source.
TEST(LasStreamWriter, BatchesGiveTheBytesOfTheWholeCloud) {
  test::TempDir dir;
  for (auto [minor, format] : {std::pair{2, 3}, {4, 7}}) {
    const auto in = dir.write("in.las", test::makeLas(manyPoints(minor, format)));
    auto source = std::make_shared<LasHeader>(readLasHeaderWithRecords(in));
    const PointCloud cloud = readLas(in);
    ASSERT_EQ(cloud.count, 5000u);
    for (std::uint32_t chunk : {0u, 1000u}) {
      SCOPED_TRACE("format " + std::to_string(format) + " chunk " + std::to_string(chunk));
      const LasWriteOptions options{.source = source, .laz_chunk_points = chunk};
      writeLas(cloud, dir / "whole.las", options);
      std::filesystem::remove(dir / "streamed.las");
      LasStreamWriter writer(dir / "streamed.las", cloud, cloud.count, options);
      EXPECT_EQ(writer.plan().point_format, format);
      std::uint64_t first = 0;
      for (std::uint64_t n : {1, 999, 1, 2500, 1499}) {
        writer.write(slicePoints(cloud, first, n));
        first += n;
      }
      ASSERT_EQ(first, cloud.count);
      EXPECT_FALSE(std::filesystem::exists(dir / "streamed.las")) << "renamed only at the end";
      writer.finish();
      const std::string whole = fileBytes(dir / "whole.las");
      EXPECT_GT(whole.size(), chunk ? 5000u * 4 : 5000u * 34);  // every point is in
      EXPECT_TRUE(whole == fileBytes(dir / "streamed.las"));
    }
  }
}

// Memory is a batch and the blocks in flight, not the file: 2 M points (48 MB of LAS records)
// streamed in batches of 65 536, LAS and LAZ (chunks of 1 000 points, so the chunks in flight are
// small whatever the core count), with no single allocation of 4 MB (allocation_counter.h).
TEST(LasStreamWriter, HoldsABatchNotTheFile) {
  test::TempDir dir;
  constexpr std::size_t kPoints = 2000000, kBatch = 65536;
  PointCloud cloud;
  cloud.count = kPoints;
  cloud.positions = Column<Int3>(kPoints);
  ScalarColumn distance{"distance", ScalarType::Float32, ByteBuffer(kPoints * 4)};
  for (std::size_t i = 0; i < kPoints; ++i) {
    cloud.positions[i] = {int(i % 1000), int(i / 1000), int(i % 7)};
    distance.as<float>()[i] = float(i) * 0.25f;
  }
  cloud.scalars.push_back(std::move(distance));
  for (std::uint32_t chunk : {0u, 1000u}) {
    SCOPED_TRACE(chunk);
    const auto path = dir / (chunk ? "out.laz" : "out.las");
    std::uint64_t largest = 0;
    {
      test::AllocationScope allocations;
      LasStreamWriter writer(path, slicePoints(cloud, 0, 1), kPoints, {.laz_chunk_points = chunk});
      for (std::size_t first = 0; first < kPoints; first += kBatch) {
        writer.write(slicePoints(cloud, first, std::min(kBatch, kPoints - first)));
      }
      writer.finish();
      largest = allocations.largest();
    }
    EXPECT_LT(largest, std::uint64_t(4) << 20);
    const PointCloud back = readPointFile(path);
    ASSERT_EQ(back.count, kPoints);
    EXPECT_EQ(back.positions[kPoints - 1], cloud.positions[kPoints - 1]);
    EXPECT_EQ(back.findScalar("distance")->valueAsDouble(kPoints - 1), (kPoints - 1) * 0.25);
    if (!chunk) {
      EXPECT_EQ(std::filesystem::file_size(path), 227 + 54 + 192 + kPoints * 24);
    }
  }
}

// The format is decided before the first record, from the layout cloud's maxima: a one-point
// layout holding a class of 40 gives LAS 1.4 format 6 to batches whose first ones have classes
// below 32, as writeLas does for the whole; a writer dropped unfinished leaves no file.
TEST(LasStreamWriter, TheLayoutsMaximaDecideTheFormatOfEveryBatch) {
  test::TempDir dir;
  PointCloud cloud;
  cloud.count = 3000;
  cloud.positions = Column<Int3>(cloud.count);
  cloud.classification = Column<std::uint8_t>(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    cloud.positions[i] = {int(i), -int(i) * 3, int(i % 17)};
    cloud.classification[i] = std::uint8_t(i == 2500 ? 40 : i % 32);
  }
  writeLas(cloud, dir / "whole.las");
  EXPECT_EQ(readLasHeader(dir / "whole.las").point_format, 6);
  {
    LasStreamWriter unfinished(dir / "unfinished.las", slicePoints(cloud, 0, 1), cloud.count);
    EXPECT_EQ(unfinished.plan().point_format, 0);
    unfinished.write(slicePoints(cloud, 0, 2000));
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename(), "whole.las");  // neither the file nor its partial copy
  }
  LasStreamWriter writer(dir / "streamed.las", slicePoints(cloud, 2500, 1), cloud.count);
  EXPECT_EQ(writer.plan().minor_version, 4);
  EXPECT_EQ(writer.plan().point_format, 6);
  writer.write(slicePoints(cloud, 0, 2000));
  writer.write(slicePoints(cloud, 2000, 1000));
  writer.finish();
  EXPECT_TRUE(fileBytes(dir / "whole.las") == fileBytes(dir / "streamed.las"));
  const PointCloud back = readLas(dir / "streamed.las");
  ASSERT_EQ(back.count, cloud.count);
  EXPECT_EQ(back.classification[2500], 40);
  EXPECT_EQ(back.classification[2499], 2499 % 32);
}

// 8-bit values in the 16-bit colour fields (most LAS writers) and true 16-bit ones: both come
// back as stored, in every format, with the source's format and version.
TEST(LasWriter, RecordsOfASourceAreKeptByteForByte) {
  test::TempDir dir;
  for (auto [minor, format] : {std::pair{2, 0},
                               {2, 1},
                               {2, 2},
                               {2, 3},
                               {3, 4},
                               {3, 5},
                               {4, 6},
                               {4, 7},
                               {4, 8},
                               {4, 9},
                               {4, 10}}) {
    for (bool eight_bit : {true, false}) {
      SCOPED_TRACE("format " + std::to_string(format) + (eight_bit ? " 8-bit" : " 16-bit"));
      LasTestFile file = manyPoints(minor, format);
      for (std::size_t i = 0; i < file.points.size(); ++i) {
        auto& p = file.points[i];
        p.red = std::uint16_t(eight_bit ? i % 256 : i * 37);
        p.green = std::uint16_t(eight_bit ? 84 : 1 + i * 3);
        p.blue = std::uint16_t(eight_bit ? (i * 7) % 256 : 65535 - i);
      }
      const std::string bytes = test::makeLas(file);
      const auto in = dir.write("in.las", bytes);
      auto source = std::make_shared<LasHeader>(readLasHeaderWithRecords(in));
      const auto out = dir / "out.las";
      writeLas(readLas(in), out, {.source = source});
      const std::string written = fileBytes(out);
      EXPECT_EQ(int(std::uint8_t(written[104])), format);
      EXPECT_EQ(int(written[25]), minor);
      ASSERT_TRUE(recordsOf(written) == recordsOf(bytes));
    }
  }
}

TEST(LasWriter, PlyUcharColoursScaleTo16BitsAndBack) {
  test::TempDir dir;
  PointCloud cloud = readLasFromMemory(asBytes(test::makeLas(manyPoints(2, 2))), "in");
  cloud.stored_colors = {};  // as from a PLY: 8-bit colours only
  cloud.colors[0] = {84, 0, 255, 255};
  writeLas(cloud, dir / "a.las");
  const PointCloud back = readLas(dir / "a.las");
  EXPECT_EQ(back.stored_colors[0], (Rgb16{84 * 257, 0, 65535}));
  EXPECT_EQ(back.colors[0], (Rgba8{84, 0, 255, 255}));
  writePly(back, dir / "b.ply");
  EXPECT_EQ(readPly(dir / "b.ply").colors[0], (Rgba8{84, 0, 255, 255}));
}

TEST(LasWriter, AFieldTheSourceFormatLacksGrowsTheFormatAndIsNamed) {
  test::TempDir dir;
  const auto in = dir.write("in.las", test::makeLas(manyPoints(2, 1)));
  auto source = std::make_shared<LasHeader>(readLasHeaderWithRecords(in));
  PointCloud cloud = readLas(in);
  for (ScalarColumn& column : cloud.scalars) {
    if (column.name == "return_number") column.as<std::uint8_t>()[0] = 9;
  }
  const LasWritePlan plan = planLasWrite(cloud, {.source = source});
  EXPECT_EQ(plan.point_format, 6);
  EXPECT_EQ(plan.minor_version, 4);
  ASSERT_EQ(plan.changes.size(), 2u);
  EXPECT_NE(plan.changes[0].find("point format 1 -> 6"), std::string::npos) << plan.changes[0];
  EXPECT_NE(plan.changes[0].find("return_number above 7"), std::string::npos) << plan.changes[0];
  EXPECT_NE(plan.changes[1].find("LAS 1.2 -> 1.4"), std::string::npos) << plan.changes[1];
  EXPECT_THROW(planLasWrite(cloud, {.minor_version = 2, .point_format = 6, .source = source}),
               std::invalid_argument);
}

TEST(LasWriter, CrsRecordsAreCopied) {
  test::TempDir dir;
  LasTestFile file = manyPoints(2, 1);
  std::string keys;
  for (std::uint16_t v : {1, 1, 0, 1, 3072, 0, 1, 32632})
    keys.append(reinterpret_cast<const char*>(&v), 2);
  file.vlrs.push_back({"LASF_Projection", 34735, keys});
  auto in = dir.write("in.las", test::makeLas(file));
  LasHeader header = readLasHeader(in);
  auto out = dir / "out.las";
  writeLas(readLas(in), out, {.vlrs = header.vlrs});
  EXPECT_EQ(readLasHeader(out).crs.projected_epsg, 32632);
}

TEST(LasWriter, LasToPlyToLasKeepsEveryValue) {
  test::TempDir dir;
  for (int format : {3, 8}) {
    PointCloud source =
        readLasFromMemory(asBytes(test::makeLas(manyPoints(format >= 6 ? 4 : 2, format))), "in");
    auto ply = dir / "mid.ply";
    auto las = dir / "back.las";
    writePly(source, ply);  // an exception here fails the test
    writeLas(readPly(ply), las);
    PointCloud back = readLas(las);
    // Positions go through PLY as doubles; the LAS writer gets them back under the PLY reader's
    // quantization, so compare world coordinates to the source's scale.
    ASSERT_EQ(back.count, source.count);
    for (std::size_t i = 0; i < source.count; ++i) {
      ASSERT_NEAR(back.worldX(i), source.worldX(i), source.quantization.scale[0] * 0.5);
      ASSERT_NEAR(back.worldY(i), source.worldY(i), source.quantization.scale[1] * 0.5);
      ASSERT_NEAR(back.worldZ(i), source.worldZ(i), source.quantization.scale[2] * 0.5);
      ASSERT_EQ(back.colors[i], source.colors[i]);
      ASSERT_EQ(back.intensity[i], source.intensity[i]);
      ASSERT_EQ(back.classification[i], source.classification[i]);
    }
    for (const ScalarColumn& column : source.scalars) {
      const ScalarColumn* other = back.findScalar(column.name);
      ASSERT_NE(other, nullptr) << column.name;
      for (std::size_t i = 0; i < source.count; ++i) {
        ASSERT_EQ(column.valueAsDouble(i), other->valueAsDouble(i)) << column.name;
      }
    }
  }
}

TEST(LasWriter, TextToLasKeepsTheDecimalValues) {
  test::TempDir dir;
  auto in = dir.write("in.xyz",
                      "x y z red green blue intensity classification\n"
                      "512345.678 5401234.567 123.45 10 20 30 700 2\n"
                      "512346.001 5401235.999 -0.05 255 0 128 0 6\n");
  PointCloud text = readPointFile(in);
  auto out = dir / "out.las";
  writePointFile(text, out);
  LasHeader header = readLasHeader(out);
  EXPECT_EQ(header.quantization.scale, (std::array<double, 3>{0.001, 0.001, 0.01}));
  EXPECT_EQ(header.point_format, 2);
  PointCloud las = readLas(out);
  expectSameCloud(text, las, false);
  // Offset 0 where the int32 range allows it: x is held as the written digits.
  EXPECT_EQ(las.positions[0].x, 512345678);
  EXPECT_NEAR(las.worldX(0), 512345.678, 1e-9);
  EXPECT_NEAR(las.worldZ(1), -0.05, 1e-12);
  EXPECT_EQ(las.colors[1], (Rgba8{255, 0, 128, 255}));
}

}  // namespace
}  // namespace parallax

namespace parallax {
namespace {

// encodeLasHeader, the one header encoder of the LAS, LAZ and COPC writers: every field it writes
// read back by parseLasHeader, for each version, with the byte offsets of R15 Table 3.
TEST(LasHeaderEncoder, WritesEveryVersionsFieldsWhereTheReaderFindsThem) {
  for (const int minor : {0, 1, 2, 3, 4}) {
    SCOPED_TRACE("LAS 1." + std::to_string(minor));
    LasHeader in;
    in.version_minor = std::uint8_t(minor);
    in.file_source_id = 513;
    in.global_encoding = minor == 4 ? 17 : 1;
    for (std::size_t i = 0; i < in.guid.size(); ++i) in.guid[i] = std::byte(i + 1);
    in.system_identifier = "a system identifier over thirty-two bytes long";
    in.generating_software = "tests";
    in.creation_day = 45;
    in.creation_year = 2026;
    in.point_format = minor == 4 ? 6 : 1;
    in.record_length = std::uint16_t(lasPointFormatSize(in.point_format));
    in.point_data_offset = std::uint32_t(lasHeaderSizeFor(minor));
    in.point_count = 0;
    in.quantization.scale = {0.01, 0.001, 0.5};
    in.quantization.offset = {100.0, -200.0, 3.0};
    const std::vector<std::byte> bytes = encodeLasHeader(in, false);
    ASSERT_EQ(bytes.size(), minor == 4 ? 375u : minor == 3 ? 235u : 227u);
    const LasHeader out = parseLasHeader(bytes, "encoded.las");
    EXPECT_EQ(out.version_minor, minor);
    EXPECT_EQ(out.file_source_id, 513);
    EXPECT_EQ(out.global_encoding, in.global_encoding);
    EXPECT_EQ(out.guid, in.guid);
    EXPECT_EQ(out.system_identifier, "a system identifier over thirty-");  // 32 bytes kept
    EXPECT_EQ(out.generating_software, "tests");
    EXPECT_EQ(out.creation_day, 45);
    EXPECT_EQ(out.creation_year, 2026);
    EXPECT_EQ(out.header_size, bytes.size());
    EXPECT_EQ(out.point_format, in.point_format);
    EXPECT_EQ(out.record_length, in.record_length);
    EXPECT_EQ(out.point_count, 0u);
    EXPECT_EQ(out.quantization.scale, in.quantization.scale);
    EXPECT_EQ(out.quantization.offset, in.quantization.offset);
  }
}

// The counts and bounds: legacy counts for formats 0-5 only, 1.4's 64-bit ones, max before min.
TEST(LasHeaderEncoder, WritesCountsAndBoundsAtTheirOffsets) {
  LasHeader in;
  in.version_minor = 4;
  in.point_format = 3;
  in.record_length = 34;
  in.point_count = 7;
  for (std::size_t r = 0; r < 15; ++r) in.points_by_return[r] = r + 1;
  in.bounds.min = {1.5, 2.5, 3.5};
  in.bounds.max = {4.5, 5.5, 6.5};
  in.evlr_offset = 1234;
  in.evlr_count = 2;
  std::vector<std::byte> bytes = encodeLasHeader(in, true);
  EXPECT_EQ(std::to_integer<int>(bytes[104]), 3 | 0x80);  // LASzip's bit
  EXPECT_EQ(loadLE<std::uint32_t>(bytes.data() + 107), 7u);
  for (std::size_t r = 0; r < 5; ++r) {
    EXPECT_EQ(loadLE<std::uint32_t>(bytes.data() + 111 + 4 * r), r + 1);
  }
  const double expected_bounds[] = {4.5, 1.5, 5.5, 2.5, 6.5, 3.5};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(loadLE<double>(bytes.data() + 179 + 8 * i), expected_bounds[i]);
  }
  EXPECT_EQ(loadLE<std::uint64_t>(bytes.data() + 235), 1234u);
  EXPECT_EQ(loadLE<std::uint32_t>(bytes.data() + 243), 2u);
  EXPECT_EQ(loadLE<std::uint64_t>(bytes.data() + 247), 7u);
  for (std::size_t r = 0; r < 15; ++r) {
    EXPECT_EQ(loadLE<std::uint64_t>(bytes.data() + 255 + 8 * r), r + 1);
  }
  // Formats 6-10: the legacy counts are zero (R15 2.4).
  in.point_format = 6;
  bytes = encodeLasHeader(in, false);
  EXPECT_EQ(std::to_integer<int>(bytes[104]), 6);
  EXPECT_EQ(loadLE<std::uint32_t>(bytes.data() + 107), 0u);
  EXPECT_EQ(loadLE<std::uint32_t>(bytes.data() + 111), 0u);
  EXPECT_EQ(loadLE<std::uint64_t>(bytes.data() + 247), 7u);
  // No points: the bounds stay zero.
  in.point_count = 0;
  bytes = encodeLasHeader(in, false);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(loadLE<double>(bytes.data() + 179 + 8 * i), 0.0);
}

}  // namespace
}  // namespace parallax
