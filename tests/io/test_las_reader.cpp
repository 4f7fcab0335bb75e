#include "io/las_reader.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"
#include "io/point_file.h"
#include "io/test_las_builder.h"
#include "support/allocation_counter.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::LasTestFile;
using test::LasTestPoint;
using test::makeLas;

PointCloud readBytes(const std::string& s) {
  return readLasFromMemory(asBytes(s), "t.las");
}

template <class T>
T scalarAt(const PointCloud& cloud, const std::string& name, std::size_t i) {
  const ScalarColumn* column = cloud.findScalar(name);
  EXPECT_NE(column, nullptr) << name;
  return column ? column->as<T>()[i] : T{};
}

std::vector<LasTestPoint> samplePoints(bool extended) {
  LasTestPoint a;
  a.x = 100, a.y = -200, a.z = 300;
  a.intensity = 65535;
  a.return_number = extended ? 11 : 5, a.number_of_returns = extended ? 15 : 7;
  a.scan_direction = 1, a.edge = 0;
  a.classification = extended ? 200 : 31, a.flags = extended ? 9 : 5;
  a.channel = extended ? 3 : 0;
  a.scan_angle = extended ? -15000 : -90;
  a.user_data = 7, a.point_source_id = 65000, a.gps_time = 123456.789;
  a.red = 65535, a.green = 257, a.blue = 0, a.nir = 4242;
  LasTestPoint b;
  b.x = INT32_MIN, b.y = INT32_MAX, b.z = 0;
  b.intensity = 12, b.return_number = 1, b.number_of_returns = 2, b.edge = 1;
  b.classification = 2, b.scan_angle = 90, b.gps_time = -1.5;
  b.red = 512, b.green = 1000, b.blue = 65280, b.nir = 1;
  return {a, b};
}

TEST(LasReader, EveryPointFormatOfEveryVersion) {
  for (int minor = 0; minor <= 4; ++minor) {
    for (int format = 0; format <= 10; ++format) {
      if (format >= 4 && format <= 5 && minor < 3) continue;
      if (format >= 6 && minor < 4) continue;
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
      const bool ext = format >= 6;
      LasTestFile file{.minor = minor, .format = format, .points = samplePoints(ext)};
      PointCloud cloud = readBytes(makeLas(file));
      ASSERT_EQ(cloud.count, 2u);
      EXPECT_EQ(cloud.positions[0], (Int3{100, -200, 300}));
      EXPECT_EQ(cloud.positions[1], (Int3{INT32_MIN, INT32_MAX, 0}));
      EXPECT_EQ(cloud.intensity[0], 65535.0f);
      EXPECT_EQ(cloud.intensity[1], 12.0f);
      EXPECT_EQ(cloud.classification[0], ext ? 200 : 31);
      EXPECT_EQ(cloud.classification[1], 2);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "return_number", 0), ext ? 11 : 5);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "number_of_returns", 0), ext ? 15 : 7);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "number_of_returns", 1), 2);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "scan_direction_flag", 0), 1);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "edge_of_flight_line", 1), 1);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "classification_flags", 0), ext ? 9 : 5);
      EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "user_data", 0), 7);
      EXPECT_EQ(scalarAt<std::uint16_t>(cloud, "point_source_id", 0), 65000);
      if (ext) {
        EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "scanner_channel", 0), 3);
        EXPECT_EQ(scalarAt<std::int16_t>(cloud, "scan_angle", 0), -15000);
        EXPECT_EQ(cloud.findScalar("scan_angle_rank"), nullptr);
      } else {
        EXPECT_EQ(scalarAt<std::int8_t>(cloud, "scan_angle_rank", 0), -90);
        EXPECT_EQ(scalarAt<std::int8_t>(cloud, "scan_angle_rank", 1), 90);
      }
      bool gps = format != 0 && format != 2;
      EXPECT_EQ(cloud.findScalar("gps_time") != nullptr, gps);
      if (gps) {
        EXPECT_EQ(scalarAt<double>(cloud, "gps_time", 0), 123456.789);
      }
      bool color =
          format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
      ASSERT_EQ(cloud.hasColors(), color);
      if (color) {
        // 16-bit colours: the nearest of value / 257.
        EXPECT_EQ(cloud.colors[0], (Rgba8{255, 1, 0, 255}));
        EXPECT_EQ(cloud.colors[1], (Rgba8{2, 4, 254, 255}));
        EXPECT_EQ(cloud.source.color, ScalarType::UInt16);
      }
      bool nir = format == 8 || format == 10;
      EXPECT_EQ(cloud.findScalar("nir") != nullptr, nir);
      if (nir) {
        EXPECT_EQ(scalarAt<std::uint16_t>(cloud, "nir", 0), 4242);
      }
      bool wave = format == 4 || format == 5 || format == 9 || format == 10;
      EXPECT_EQ(cloud.findScalar("wave_packet_size") != nullptr, wave);
    }
  }
}

TEST(LasReader, KeepsScaleAndOffsetExactly) {
  LasTestFile file{.format = 1, .points = samplePoints(false)};
  file.scale[0] = 0.001, file.scale[1] = 0.0025, file.scale[2] = 0.01;
  file.offset[0] = 500000.0, file.offset[1] = 4500000.0, file.offset[2] = -12.5;
  PointCloud cloud = readBytes(makeLas(file));
  EXPECT_EQ(cloud.quantization.scale, (std::array<double, 3>{0.001, 0.0025, 0.01}));
  EXPECT_EQ(cloud.quantization.offset, (std::array<double, 3>{500000.0, 4500000.0, -12.5}));
  EXPECT_EQ(cloud.worldX(0), 100 * 0.001 + 500000.0);
  EXPECT_EQ(cloud.bounds.max[1], double(INT32_MAX) * 0.0025 + 4500000.0);
}

TEST(LasReader, EightBitColoursInSixteenBitFieldsAreKept) {
  LasTestFile file{.format = 2, .points = samplePoints(false)};
  file.points[0].red = 255, file.points[0].green = 128, file.points[0].blue = 0;
  file.points[1].red = 1, file.points[1].green = 2, file.points[1].blue = 3;
  PointCloud cloud = readBytes(makeLas(file));
  EXPECT_EQ(cloud.colors[0], (Rgba8{255, 128, 0, 255}));
  EXPECT_EQ(cloud.colors[1], (Rgba8{1, 2, 3, 255}));
  EXPECT_EQ(cloud.source.color, ScalarType::UInt8);
}

TEST(LasReader, ExtraBytesBecomeNamedColumns) {
  LasTestFile file{.minor = 4, .format = 6, .extra_bytes = 2 + 4 + 4 + 3};
  file.vlrs.push_back({"LASF_Spec", 4,
                       test::extraBytesDescriptor(3, "amplitude") +
                           test::extraBytesDescriptor(6, "height", 0.01, 100.0) +
                           test::extraBytesDescriptor(9, "deviation") +
                           test::extraBytesDescriptor(0, "raw")});
  file.vlrs.back().data[192 * 3 + 3] = 3;  // undocumented: options = 3 bytes
  LasTestPoint p;
  std::string extra(13, '\0');
  test::putAt(extra, 0, std::uint16_t(4321));
  test::putAt(extra, 2, std::int32_t(-250));
  test::putAt(extra, 6, 1.5f);
  extra[10] = 9, extra[11] = 8, extra[12] = 7;
  p.extra.assign(extra.begin(), extra.end());
  file.points = {p};
  PointCloud cloud = readBytes(makeLas(file));
  EXPECT_EQ(scalarAt<std::uint16_t>(cloud, "amplitude", 0), 4321);
  EXPECT_EQ(cloud.findScalar("height")->type, ScalarType::Float64);
  EXPECT_DOUBLE_EQ(scalarAt<double>(cloud, "height", 0), -250 * 0.01 + 100.0);
  EXPECT_EQ(scalarAt<float>(cloud, "deviation", 0), 1.5f);
  EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "raw_0", 0), 9);
  EXPECT_EQ(scalarAt<std::uint8_t>(cloud, "raw_2", 0), 7);
}

TEST(LasReader, NormalComponentNamesOfEveryConvention) {
  EXPECT_EQ(lasNormalComponentAxis("NormalX"), 0);  // CloudCompare's and PDAL's
  EXPECT_EQ(lasNormalComponentAxis("NormalY"), 1);
  EXPECT_EQ(lasNormalComponentAxis("nz"), 2);
  EXPECT_EQ(lasNormalComponentAxis("normal_y"), 1);
  EXPECT_EQ(lasNormalComponentAxis("Norm Z"), 2);
  EXPECT_EQ(lasNormalComponentAxis("NORMAL-X"), 0);
  for (const char* other : {"normal", "x", "nxx", "snx", "normalw", "intensity", ""}) {
    EXPECT_EQ(lasNormalComponentAxis(other), -1) << other;
  }
}

// Three float or double extra bytes named as a normal's components (any order, any of the
// conventions) are the cloud's normals; anything less stays scalars under its names.
TEST(LasReader, NormalExtraBytesAreReadAsNormals) {
  {
    // CloudCompare's and PDAL's layout: float NormalX NormalY NormalZ, here after another column.
    LasTestFile file{.minor = 4, .format = 6, .extra_bytes = 2 + 12};
    file.vlrs.push_back(
        {"LASF_Spec", 4,
         test::extraBytesDescriptor(3, "amplitude") + test::extraBytesDescriptor(9, "NormalX") +
             test::extraBytesDescriptor(9, "NormalY") + test::extraBytesDescriptor(9, "NormalZ")});
    LasTestPoint p;
    std::string extra(14, '\0');
    test::putAt(extra, 0, std::uint16_t(4321));
    test::putAt(extra, 2, 0.6f);
    test::putAt(extra, 6, -0.8f);
    test::putAt(extra, 10, 0.0f);
    p.extra.assign(extra.begin(), extra.end());
    file.points = {p, p};
    PointCloud cloud = readBytes(makeLas(file));
    ASSERT_TRUE(cloud.hasNormals());
    EXPECT_EQ(cloud.normals[1].x, 0.6f);
    EXPECT_EQ(cloud.normals[1].y, -0.8f);
    EXPECT_EQ(cloud.normals[1].z, 0.0f);
    EXPECT_EQ(cloud.source.normal, ScalarType::Float32);
    EXPECT_EQ(scalarAt<std::uint16_t>(cloud, "amplitude", 1), 4321);
    for (const char* name : {"NormalX", "NormalY", "NormalZ"}) {
      EXPECT_EQ(cloud.findScalar(name), nullptr) << name;
    }
  }
  {
    // Doubles named normal_z, normal_x, normal_y, in that order: placed by name.
    LasTestFile file{.minor = 4, .format = 0, .extra_bytes = 24};
    file.vlrs.push_back({"LASF_Spec", 4,
                         test::extraBytesDescriptor(10, "normal_z") +
                             test::extraBytesDescriptor(10, "normal_x") +
                             test::extraBytesDescriptor(10, "normal_y")});
    LasTestPoint p;
    std::string extra(24, '\0');
    test::putAt(extra, 0, 0.25);
    test::putAt(extra, 8, -0.5);
    test::putAt(extra, 16, 0.125);
    p.extra.assign(extra.begin(), extra.end());
    file.points = {p};
    PointCloud cloud = readBytes(makeLas(file));
    ASSERT_TRUE(cloud.hasNormals());
    EXPECT_EQ(cloud.normals[0], (Float3{-0.5f, 0.125f, 0.25f}));
    EXPECT_EQ(cloud.source.normal, ScalarType::Float64);
    EXPECT_EQ(cloud.findScalar("normal_x"), nullptr);
  }
  {
    // Two components only, or one stored as a scaled integer: no normals, the scalars kept.
    for (const bool scaled : {false, true}) {
      SCOPED_TRACE(scaled);
      LasTestFile file{.minor = 4, .format = 0, .extra_bytes = scaled ? 10 : 8};
      std::string descriptors =
          test::extraBytesDescriptor(9, "nx") + test::extraBytesDescriptor(9, "ny");
      if (scaled) descriptors += test::extraBytesDescriptor(4, "nz", 0.001);
      file.vlrs.push_back({"LASF_Spec", 4, descriptors});
      LasTestPoint p;
      std::string extra(std::size_t(file.extra_bytes), '\0');
      test::putAt(extra, 0, 1.0f);
      if (scaled) test::putAt(extra, 8, std::int16_t(-1000));
      p.extra.assign(extra.begin(), extra.end());
      file.points = {p};
      PointCloud cloud = readBytes(makeLas(file));
      EXPECT_FALSE(cloud.hasNormals());
      EXPECT_EQ(scalarAt<float>(cloud, "nx", 0), 1.0f);
      EXPECT_EQ(scalarAt<float>(cloud, "ny", 0), 0.0f);
      if (scaled) {
        EXPECT_DOUBLE_EQ(scalarAt<double>(cloud, "nz", 0), -1.0);
      }
    }
  }
}

TEST(LasReader, ReportsGeoTiffAndWktCrs) {
  LasTestFile file{.format = 0, .points = samplePoints(false)};
  std::string keys;
  for (std::uint16_t v : {1, 1, 0, 2, 3072, 0, 1, 26915, 4096, 0, 1, 5703}) {
    keys.append(reinterpret_cast<const char*>(&v), 2);
  }
  file.vlrs.push_back({"LASF_Projection", 34735, keys});
  file.vlrs.push_back({"LASF_Projection", 34737, std::string("NAD83 / UTM zone 15N|\0", 22)});
  LasHeader header = parseLasHeader(asBytes(makeLas(file)), "t.las");
  EXPECT_EQ(header.crs.projected_epsg, 26915);
  EXPECT_EQ(header.crs.vertical_epsg, 5703);
  EXPECT_EQ(header.crs.summary(),
            "EPSG:26915 + EPSG:5703 \"NAD83 / UTM zone 15N|\" (GeoTIFF keys)");
  EXPECT_NE(describeLasHeader(header).find("EPSG:26915"), std::string::npos);

  LasTestFile wkt{.minor = 4, .format = 6, .global_encoding = 16};
  wkt.vlrs.push_back({"LASF_Projection", 2112,
                      std::string("PROJCS[\"WGS 84 / UTM zone 32N\",GEOGCS[\"WGS 84\"]]\0", 47)});
  header = parseLasHeader(asBytes(makeLas(wkt)), "t.las");
  EXPECT_EQ(header.crs.summary(), "WGS 84 / UTM zone 32N (WKT)");
  EXPECT_TRUE(header.crs.wkt.starts_with("PROJCS["));
}

TEST(LasReader, LazBitWithoutTheLaszipVlrIsAnError) {
  std::string bytes = makeLas({.format = 3, .points = samplePoints(false)});
  bytes[104] = char(3 | 0x80);  // LASzip's compression bit, but no "laszip encoded" VLR
  EXPECT_EQ(detectPointFormatFromMemory(asBytes(bytes)), PointFormat::Laz);
  try {
    readBytes(bytes);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().byte_offset, 104u);
    EXPECT_NE(e.info().expected.find("laszip encoded"), std::string::npos) << e.what();
  }
}

// Runs the reader on `bytes` and returns the error, failing the test when there is none.
InputErrorInfo lasErrorOf(const std::string& bytes) {
  try {
    readBytes(bytes);
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "t.las");
    return e.info();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(LasReader, BadInputIsNamedPrecisely) {
  const std::string good = makeLas({.minor = 2, .format = 3, .points = samplePoints(false)});
  std::string bytes = good;
  bytes[0] = 'X';
  EXPECT_EQ(lasErrorOf(bytes).property, "file signature");

  EXPECT_EQ(lasErrorOf(good.substr(0, 100)).property, "header");

  bytes = good;
  test::putAt(bytes, 25, std::uint8_t(7));
  EXPECT_EQ(lasErrorOf(bytes).property, "version");

  bytes = good;
  test::putAt(bytes, 94, std::uint16_t(60000));
  EXPECT_EQ(lasErrorOf(bytes).property, "header size");

  bytes = good;
  test::putAt(bytes, 96, std::uint32_t(1u << 30));
  auto info = lasErrorOf(bytes);
  EXPECT_EQ(info.property, "offset to point data");
  EXPECT_EQ(info.byte_offset, 96u);

  // Counts far more than the file holds, and one a file could plausibly hold (10 M points,
  // columns of hundreds of MB): the error comes before any column is allocated (malloc and mmap
  // counted, allocation_counter.h).
  for (const std::uint32_t count : {4000000000u, 10000000u}) {
    bytes = good;
    test::putAt(bytes, 107, count);
    test::AllocationScope allocations;
    info = lasErrorOf(bytes);
    EXPECT_LT(allocations.bytes(), 1u << 20) << count;
    EXPECT_EQ(info.property, "number of point records");
    EXPECT_NE(info.found.find(std::to_string(count)), std::string::npos);
  }

  EXPECT_EQ(lasErrorOf(good.substr(0, good.size() - 1)).property, "number of point records");

  bytes = good;
  test::putAt(bytes, 104, std::uint8_t(11));
  EXPECT_EQ(lasErrorOf(bytes).property, "point data format");

  bytes = good;
  test::putAt(bytes, 105, std::uint16_t(20));  // below format 3's 34 bytes
  EXPECT_EQ(lasErrorOf(bytes).property, "point data record length");

  bytes = good;
  test::putAt(bytes, 100, std::uint32_t(3));  // VLRs that are not there
  EXPECT_NE(lasErrorOf(bytes).property.find("VLR"), std::string::npos);

  bytes = good;
  test::putAt(bytes, 131, 0.0);
  EXPECT_EQ(lasErrorOf(bytes).property, "x scale factor");

  LasTestFile vlr_file{.format = 0, .points = samplePoints(false)};
  vlr_file.vlrs.push_back({"test", 1, "payload"});
  bytes = makeLas(vlr_file);
  test::putAt(bytes, 227 + 20, std::uint16_t(5000));  // payload past the point data
  EXPECT_EQ(lasErrorOf(bytes).property, "VLR 1 record length");

  LasTestFile extra{.minor = 4, .format = 6, .extra_bytes = 2};
  extra.vlrs.push_back({"LASF_Spec", 4, test::extraBytesDescriptor(10, "too_big")});
  EXPECT_EQ(lasErrorOf(makeLas(extra)).property, "extra bytes VLR");
}

TEST(LasReader, HeaderOfEveryTruncationIsAnErrorNotACrash) {
  const std::string good = makeLas({.minor = 4, .format = 8, .points = samplePoints(true)});
  for (std::size_t size = 0; size < good.size(); ++size) {
    EXPECT_THROW(readBytes(good.substr(0, size)), InputError) << size;
  }
}

TEST(LasReader, ChunksMatchTheWholeRead) {
  test::TempDir dir;
  LasTestFile file{.minor = 3, .format = 3};
  for (int i = 0; i < 1000; ++i) {
    LasTestPoint p;
    p.x = i, p.y = -i, p.z = i * 3, p.red = std::uint16_t(i * 50);
    p.gps_time = i * 0.5;
    file.points.push_back(p);
  }
  auto path = dir.write("chunks.las", makeLas(file));
  PointCloud whole = readLas(path);
  LasChunkReader reader(path);
  EXPECT_EQ(reader.pointCount(), 1000u);
  PointCloud chunk;
  std::size_t at = 0;
  while (reader.next(chunk, 300)) {
    for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
      ASSERT_EQ(chunk.positions[i], whole.positions[at]);
      ASSERT_EQ(chunk.colors[i], whole.colors[at]);
      ASSERT_EQ(chunk.scalars.back().as<double>()[i], whole.scalars.back().as<double>()[at]);
    }
  }
  EXPECT_EQ(at, 1000u);
  EXPECT_EQ(detectPointFormat(path), PointFormat::Las);
  EXPECT_EQ(readPointFile(path).count, 1000u);
}

}  // namespace
}  // namespace parallax
