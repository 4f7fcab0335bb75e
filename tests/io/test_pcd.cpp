// PCD: exact values of every encoding (files written in the test, byte by byte), NaN points,
// fields of every type, COUNT > 1, packed colours, round trips through the writer, bad input with
// its line or offset and field, and PDAL's test files beside their LAS twins.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "io/las_reader.h"
#include "io/pcd_reader.h"
#include "io/pcd_writer.h"
#include "io/point_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

const std::filesystem::path kFormatsData = PARALLAX_SHARED_DATA "/formats";

PointCloud readString(const std::string& text) {
  return readPcdFromMemory({reinterpret_cast<const std::byte*>(text.data()), text.size()}, "t.pcd",
                           {.parallel = false});
}

InputErrorInfo errorOf(const std::string& text) {
  try {
    readString(text);
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "t.pcd");
    return e.info();
  }
  ADD_FAILURE() << "no error for " << text.substr(0, 200);
  return {};
}

std::string header(const std::string& fields, const std::string& size, const std::string& type,
                   const std::string& count, int width, int height, const std::string& data) {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type +
         "\nCOUNT " + count + "\nWIDTH " + std::to_string(width) + "\nHEIGHT " +
         std::to_string(height) + "\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS " +
         std::to_string(width * height) + "\nDATA " + data + "\n";
}

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

const ScalarColumn& scalar(const PointCloud& cloud, const std::string& name) {
  const ScalarColumn* column = cloud.findScalar(name);
  EXPECT_NE(column, nullptr) << name;
  static ScalarColumn none;
  return column ? *column : none;
}

TEST(PcdReader, AsciiExactValuesAndPackedFloatColour) {
  // rgb as a float: the float whose bits are 0x00FF8001 (r 255, g 128, b 1), written by its value.
  const float packed = std::bit_cast<float>(std::uint32_t(0x00FF8001));
  char packed_text[64];
  std::snprintf(packed_text, sizeof packed_text, "%.9g", double(packed));
  const std::string text = header("x y z rgb intensity label", "4 4 4 4 4 2", "F F F F F U",
                                  "1 1 1 1 1 1", 2, 1, "ascii") +
                           "1.5 -2.25 3 " + packed_text + " 0.5 7\n" + "10 20 30.125 0 1 65535\n";
  const PointCloud cloud = readString(text);
  ASSERT_EQ(cloud.count, 2u);
  EXPECT_EQ(cloud.worldX(0), 1.5);
  EXPECT_EQ(cloud.worldY(0), -2.25);
  EXPECT_EQ(cloud.worldZ(1), 30.125);
  EXPECT_EQ(cloud.colors[0], (Rgba8{255, 128, 1, 255}));
  EXPECT_EQ(cloud.colors[1], (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(cloud.intensity[0], 0.5f);
  EXPECT_EQ(scalar(cloud, "label").type, ScalarType::UInt16);
  EXPECT_EQ(scalar(cloud, "label").as<std::uint16_t>()[1], 65535);
  EXPECT_EQ(cloud.source.position, ScalarType::Float32);
  EXPECT_EQ(cloud.source.order, (std::vector<std::string>{"x", "y", "z", "red", "green", "blue",
                                                          "intensity", "label"}));
}

TEST(PcdReader, BinaryEveryTypeNaNPointsSkippedOrganised) {
  // 2 x 2 organised cloud, the second point invalid (NaN), fields of every type, a COUNT 2 field
  // and a padding field.
  std::string text =
      header("x y z rgba i8 u8 i16 i32 u32 f64 big pair _", "8 8 8 4 1 1 2 4 4 8 8 4 2",
             "F F F U I U I I U F U F U", "1 1 1 1 1 1 1 1 1 1 1 2 1", 2, 2, "binary");
  const double nan = std::nan("");
  for (int i = 0; i < 4; ++i) {
    put(text, i == 1 ? nan : 1000000.125 + i);
    put(text, 2.0 * i);
    put(text, -3.5);
    put(text, std::uint32_t(0x80102030u + std::uint32_t(i)));
    put(text, std::int8_t(-100 + i));
    put(text, std::uint8_t(200 + i));
    put(text, std::int16_t(-30000 + i));
    put(text, std::int32_t(-2000000000 + i));
    put(text, std::uint32_t(4000000000u + std::uint32_t(i)));
    put(text, 0.1 * i);
    put(text, std::uint64_t(1) << 52 | std::uint64_t(i));
    put(text, float(i) + 0.25f);
    put(text, float(i) + 0.75f);
    put(text, std::uint16_t(0xDEAD));
  }
  text += std::string(100, '\0');  // PCL pads binary files with zeros
  const PointCloud cloud = readString(text);
  ASSERT_EQ(cloud.count, 3u);  // the NaN point skipped
  EXPECT_EQ(cloud.worldX(0), 1000000.125);
  EXPECT_EQ(cloud.worldX(1), 1000002.125);  // point 2 of the file
  EXPECT_EQ(cloud.worldY(2), 6.0);
  EXPECT_EQ(cloud.colors[1], (Rgba8{0x10, 0x20, 0x32, 0x80}));
  EXPECT_TRUE(cloud.source.has_alpha);
  EXPECT_EQ(scalar(cloud, "i8").as<std::int8_t>()[1], -98);
  EXPECT_EQ(scalar(cloud, "u8").as<std::uint8_t>()[2], 203);
  EXPECT_EQ(scalar(cloud, "i16").as<std::int16_t>()[0], -30000);
  EXPECT_EQ(scalar(cloud, "i32").as<std::int32_t>()[2], -1999999997);
  EXPECT_EQ(scalar(cloud, "u32").as<std::uint32_t>()[2], 4000000003u);
  EXPECT_EQ(scalar(cloud, "f64").as<double>()[1], 0.1 * 2);
  EXPECT_EQ(scalar(cloud, "big").type, ScalarType::Float64);
  EXPECT_EQ(scalar(cloud, "big").as<double>()[2], double(std::uint64_t(1) << 52 | 3));
  EXPECT_EQ(scalar(cloud, "pair_0").as<float>()[0], 0.25f);
  EXPECT_EQ(scalar(cloud, "pair_1").as<float>()[2], 3.75f);
  EXPECT_EQ(cloud.findScalar("_"), nullptr);
}

TEST(PcdReader, NormalsAndHeaderWithoutOptionalLines) {
  // PCD 0.6-style: no VIEWPOINT, no COUNT, no HEIGHT; POINTS from WIDTH.
  const PointCloud cloud = readString(
      "VERSION .6\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\n"
      "WIDTH 1\nDATA ascii\n1 2 3 0 0.6 0.8\n");
  ASSERT_EQ(cloud.count, 1u);
  EXPECT_EQ(cloud.normals[0], (Float3{0, 0.6f, 0.8f}));
}

TEST(PcdReader, ViewpointAndOrganisedSizeInTheChunkReaderHeader) {
  test::TempDir dir;
  std::string text = header("x y z", "4 4 4", "F F F", "1 1 1", 3, 2, "ascii");
  for (int i = 0; i < 6; ++i) text += i == 4 ? "nan nan nan\n" : std::to_string(i) + " 0 0\n";
  std::ofstream(dir / "o.pcd") << text;
  PcdChunkReader reader(dir / "o.pcd");
  EXPECT_EQ(reader.header().width, 3u);
  EXPECT_EQ(reader.header().height, 2u);
  EXPECT_EQ(reader.header().viewpoint, (std::array<double, 7>{1, 2, 3, 1, 0, 0, 0}));
  EXPECT_EQ(reader.pointCount(), 5u);
  PointCloud chunk;
  std::vector<double> xs;
  while (reader.next(chunk, 2)) {
    EXPECT_LE(chunk.count, 2u);
    for (std::size_t i = 0; i < chunk.count; ++i) xs.push_back(chunk.worldX(i));
  }
  EXPECT_EQ(xs, (std::vector<double>{0, 1, 2, 3, 5}));
}

PointCloud sampleCloud() {
  const std::string text =
      header("x y z rgb normal_x normal_y normal_z intensity t", "8 8 8 4 4 4 4 4 2",
             "F F F U F F F F I", "1 1 1 1 1 1 1 1 1", 3, 1, "ascii") +
      "500000.5 4000000.25 12.125 16744448 0 0 1 0.25 -5\n"
      "500001.75 4000001 13 255 0.6 0.8 0 1 7\n"
      "499999 3999999.5 -1.5 65280 1 0 0 0 32767\n";
  return readString(text);
}

void expectSameCloud(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.count, b.count);
  ASSERT_EQ(a.attributeNames(), b.attributeNames());
  for (std::size_t i = 0; i < a.count; ++i) {
    EXPECT_EQ(a.worldX(i), b.worldX(i));
    EXPECT_EQ(a.worldY(i), b.worldY(i));
    EXPECT_EQ(a.worldZ(i), b.worldZ(i));
    if (a.hasColors()) {
      EXPECT_EQ(a.colors[i], b.colors[i]);
    }
    if (a.hasNormals()) {
      EXPECT_EQ(a.normals[i], b.normals[i]);
    }
    if (a.hasIntensity()) {
      EXPECT_EQ(a.intensity[i], b.intensity[i]);
    }
    for (std::size_t s = 0; s < a.scalars.size(); ++s) {
      EXPECT_EQ(a.scalars[s].valueAsDouble(i), b.scalars[s].valueAsDouble(i));
    }
  }
}

TEST(PcdWriter, RoundTripInEveryEncoding) {
  test::TempDir dir;
  const PointCloud cloud = sampleCloud();
  EXPECT_EQ(cloud.colors[0], (Rgba8{255, 128, 0, 255}));
  for (PcdData data : {PcdData::Ascii, PcdData::Binary, PcdData::BinaryCompressed}) {
    SCOPED_TRACE(pcdDataName(data));
    const auto path = dir / (std::string(pcdDataName(data)) + ".pcd");
    writePcd(cloud, path, {.data = data, .viewpoint = {5, 6, 7, 1, 0, 0, 0}});
    EXPECT_EQ(detectPointFormat(path), PointFormat("pcd"));
    const PointCloud back = readPointFile(path);
    expectSameCloud(cloud, back);
    EXPECT_EQ(PcdChunkReader(path).header().data, data);
    EXPECT_EQ(PcdChunkReader(path).header().viewpoint[2], 7.0);
  }
  // Through writePointFile: the extension picks PCD, --ascii its ascii encoding.
  writePointFile(cloud, dir / "a.pcd", {.ply_ascii = true});
  EXPECT_EQ(PcdChunkReader(dir / "a.pcd").header().data, PcdData::Ascii);
}

TEST(PcdWriter, ChunksOfACompressedFileEqualTheWholeRead) {
  test::TempDir dir;
  const PointCloud cloud = sampleCloud();
  writePcd(cloud, dir / "c.pcd", {.data = PcdData::BinaryCompressed});
  PcdChunkReader reader(dir / "c.pcd");
  PointCloud chunk;
  std::size_t at = 0;
  while (reader.next(chunk, 2)) {
    for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
      EXPECT_EQ(chunk.worldX(i), cloud.worldX(at));
      EXPECT_EQ(chunk.colors[i], cloud.colors[at]);
      EXPECT_EQ(chunk.scalars[0].as<std::int16_t>()[i], cloud.scalars[0].as<std::int16_t>()[at]);
    }
  }
  EXPECT_EQ(at, 3u);
}

TEST(PcdReaderErrors, MissingAndMalformedHeaderLines) {
  InputErrorInfo e = errorOf("VERSION 0.7\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
  EXPECT_EQ(e.line, 2u);
  EXPECT_EQ(e.property, "SIZE");
  EXPECT_NE(e.expected.find("FIELDS"), std::string::npos);

  e = errorOf("VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_EQ(e.expected, "3 values (one per field of FIELDS)");

  e = errorOf("FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
  EXPECT_EQ(e.line, 2u);
  EXPECT_NE(e.expected.find("field 'z'"), std::string::npos);

  e = errorOf("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nDATA ascii\n1 2 3\n");
  EXPECT_EQ(e.property, "WIDTH");  // missing, reported at the DATA line
  EXPECT_EQ(e.line, 4u);

  e = errorOf("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 3\nDATA ascii\n");
  EXPECT_EQ(e.property, "POINTS");

  e = errorOf("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA lzma\n");
  EXPECT_EQ(e.found, "'lzma'");

  e = errorOf("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n");
  EXPECT_EQ(e.property, "z");

  e = errorOf("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n");
  EXPECT_EQ(e.property, "DATA");
}

TEST(PcdReaderErrors, AsciiDataNamesLineAndField) {
  const std::string head = header("x y z label", "4 4 4 1", "F F F U", "1 1 1 1", 2, 1, "ascii");
  // The header is 11 lines: data starts on line 12.
  InputErrorInfo e = errorOf(head + "1 2 3 4\n1 2 abc 4\n");
  EXPECT_EQ(e.line, 13u);
  EXPECT_EQ(e.property, "z");
  EXPECT_EQ(e.found, "'abc'");

  e = errorOf(head + "1 2 3 256\n1 2 3 4\n");
  EXPECT_EQ(e.line, 12u);
  EXPECT_EQ(e.property, "label");

  e = errorOf(head + "1 2 3\n");
  EXPECT_EQ(e.property, "label");
  EXPECT_EQ(e.line, 12u);

  e = errorOf(head + "1 2 3 4\n");  // truncated: one line of two
  EXPECT_NE(e.expected.find("2 points"), std::string::npos);
  EXPECT_EQ(e.line, 13u);

  e = errorOf(head + "1 2 3 4\n1 2 3 4\n1 2 3 4\n");
  EXPECT_NE(e.found.find("more"), std::string::npos);
}

TEST(PcdReaderErrors, TruncatedBinaryNamesOffsetPointAndField) {
  std::string text = header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "binary");
  const std::size_t data = text.size();
  for (float v : {1.f, 2.f, 3.f, 4.f}) put(text, v);  // point 1 ends after its x
  const InputErrorInfo e = errorOf(text);
  EXPECT_EQ(e.byte_offset, data + 16);
  EXPECT_EQ(e.element, "point 1");
  EXPECT_EQ(e.property, "y");
}

TEST(PcdReaderErrors, BadCompressedSizesAndLzf) {
  test::TempDir dir;
  writePcd(sampleCloud(), dir / "c.pcd", {.data = PcdData::BinaryCompressed});
  std::ifstream in(dir / "c.pcd", std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t data = good.find("DATA binary_compressed\n") + 23;

  std::string bad = good;
  bad[data + 8] = char(0xFF);  // a back reference before the start of the output
  bad[data + 9] = char(0xFF);
  InputErrorInfo e = errorOf(bad);
  EXPECT_EQ(e.byte_offset, data + 8);
  EXPECT_EQ(e.property, "LZF data");

  e = errorOf(good.substr(0, good.size() - 5));
  EXPECT_EQ(e.property, "compressed size");
  EXPECT_EQ(e.byte_offset, data);

  bad = good;
  bad[data + 4] ^= 1;
  e = errorOf(bad);
  EXPECT_EQ(e.property, "uncompressed size");

  e = errorOf(good.substr(0, data + 3));
  EXPECT_EQ(e.property, "sizes");
}

TEST(PcdPdalFiles, AutzenEqualsItsLasTwinInEveryLasField) {
  // PDAL writes a PCD's fields under its dimension names (Intensity ReturnNumber ... GpsTime Red
  // Green Blue): they are the LAS fields, under the model's names, equal to the LAS twin's.
  const PointCloud pcd = readPointFile(kFormatsData / "pcd/autzen-utm.pcd");
  const PointCloud las = readLas(kFormatsData / "pcd/autzen-utm.las");
  ASSERT_EQ(pcd.count, 1065u);
  ASSERT_EQ(las.count, 1065u);
  ASSERT_TRUE(pcd.hasClassification());
  ASSERT_TRUE(pcd.hasColors());
  ASSERT_TRUE(pcd.hasStoredColors());  // U2 fields: given back to a LAS writer as stored
  for (const char* name : {"GpsTime", "Classification", "Red", "ReturnNumber"}) {
    EXPECT_EQ(pcd.findScalar(name), nullptr) << name;
  }
  for (std::size_t i = 0; i < pcd.count; ++i) {
    // Doubles on an int32 grid of 2^-21 m over 1.4 km: within half a step (LAS: 0.01 m).
    EXPECT_NEAR(pcd.worldX(i), las.worldX(i), 5e-7);
    EXPECT_NEAR(pcd.worldY(i), las.worldY(i), 5e-7);
    EXPECT_NEAR(pcd.worldZ(i), las.worldZ(i), 5e-7);
    EXPECT_EQ(pcd.intensity[i], las.intensity[i]);
    EXPECT_EQ(pcd.classification[i], las.classification[i]);
    EXPECT_EQ(pcd.colors[i], las.colors[i]);
    EXPECT_EQ(pcd.stored_colors[i], las.stored_colors[i]);
  }
  for (const char* name :
       {"gps_time", "return_number", "number_of_returns", "scan_direction_flag",
        "edge_of_flight_line", "scan_angle_rank", "user_data", "point_source_id"}) {
    const ScalarColumn& a = scalar(pcd, name);
    const ScalarColumn& b = scalar(las, name);
    if (a.data.empty() || b.data.empty()) continue;
    for (std::size_t i = 0; i < pcd.count; ++i) {
      ASSERT_EQ(a.valueAsDouble(i), b.valueAsDouble(i)) << name << " of point " << i;
    }
  }
}

TEST(PcdFields, SixteenBitChannelsAreStoredAndShownDividedBy257) {
  // Three 16-bit channel fields, one value over 255: kept as stored, shown as value / 257
  // rounded, as a LAS file's colours are; a field "gps_time" already present keeps "GpsTime".
  std::string text = header("x y z red green blue GpsTime gps_time", "4 4 4 2 2 2 8 8",
                            "F F F U U U F F", "1 1 1 1 1 1 1 1", 2, 1, "ascii") +
                     "0 0 0 65535 257 128 1.5 2.5\n1 2 3 0 1000 255 3.5 4.5\n";
  const PointCloud cloud = readString(text);
  ASSERT_EQ(cloud.count, 2u);
  ASSERT_TRUE(cloud.hasStoredColors());
  EXPECT_EQ(cloud.stored_colors[0], (Rgb16{65535, 257, 128}));
  EXPECT_EQ(cloud.stored_colors[1], (Rgb16{0, 1000, 255}));
  EXPECT_EQ(cloud.colors[0], (Rgba8{255, 1, 0, 255}));  // (128 + 128) / 257 = 0
  EXPECT_EQ(cloud.colors[1], (Rgba8{0, 4, 1, 255}));    // (1000 + 128) / 257 = 4
  EXPECT_EQ(cloud.source.color, ScalarType::UInt16);
  EXPECT_EQ(scalar(cloud, "GpsTime").as<double>()[1], 3.5);
  EXPECT_EQ(scalar(cloud, "gps_time").as<double>()[1], 4.5);

  // Every value below 256: 8-bit colour in 16-bit fields, shown as is.
  text = header("x y z Red Green Blue Classification", "4 4 4 2 2 2 1", "F F F U U U U",
                "1 1 1 1 1 1 1", 1, 1, "ascii") +
         "0 0 0 200 100 50 6\n";
  const PointCloud small = readString(text);
  EXPECT_EQ(small.colors[0], (Rgba8{200, 100, 50, 255}));
  EXPECT_EQ(small.stored_colors[0], (Rgb16{200, 100, 50}));
  EXPECT_EQ(small.source.color, ScalarType::UInt8);
  ASSERT_TRUE(small.hasClassification());
  EXPECT_EQ(small.classification[0], 6);
}

// Float channels and classifications may hold NaN: each gives 0 (converting NaN to an integer is
// undefined behaviour; UBSan stopped the fuzz target on a NaN classification), infinities clamp.
TEST(PcdFields, NaNChannelsAndClassificationGiveZero) {
  const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
  std::string text = header("x y z classification red green blue", "4 4 4 4 4 4 4", "F F F F F F F",
                            "1 1 1 1 1 1 1", 2, 1, "binary");
  for (float v : {0.0f, 0.0f, 0.0f, nan, nan, -inf, 300.0f}) put(text, v);
  for (float v : {1.0f, 1.0f, 1.0f, 2.4f, 10.6f, inf, nan}) put(text, v);
  const PointCloud cloud = readString(text);
  ASSERT_EQ(cloud.count, 2u);
  ASSERT_TRUE(cloud.hasClassification());
  EXPECT_EQ(cloud.classification[0], 0);
  EXPECT_EQ(cloud.classification[1], 2);
  ASSERT_TRUE(cloud.hasStoredColors());
  EXPECT_EQ(cloud.stored_colors[0], (Rgb16{0, 0, 300}));
  EXPECT_EQ(cloud.stored_colors[1], (Rgb16{11, 65535, 0}));
}

TEST(PcdPdalFiles, Utm17AsciiEqualsItsLasTwinAtFloatPrecisionAndMissingHeaderIsRefused) {
  const PointCloud pcd = readPointFile(kFormatsData / "pcd/utm17_space.pcd");
  const PointCloud las = readLas(kFormatsData / "pcd/utm17.las");
  ASSERT_EQ(pcd.count, 10u);
  ASSERT_EQ(las.count, 10u);
  for (std::size_t i = 0; i < pcd.count; ++i) {
    // The file's fields are float32: the value is the float nearest to the LAS value.
    EXPECT_EQ(pcd.worldX(i), double(float(las.worldX(i))));
    EXPECT_EQ(pcd.worldY(i), double(float(las.worldY(i))));
    EXPECT_EQ(pcd.worldZ(i), double(float(las.worldZ(i))));
  }
  EXPECT_EQ(detectPointFormat(kFormatsData / "pcd/missingheader.pcd"), PointFormat("pcd"));
  try {
    readPointFile(kFormatsData / "pcd/missingheader.pcd");
    ADD_FAILURE() << "missingheader.pcd read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().line, 1u);
    EXPECT_NE(e.info().expected.find("PCD header keyword"), std::string::npos);
  }
}

}  // namespace
}  // namespace parallax
