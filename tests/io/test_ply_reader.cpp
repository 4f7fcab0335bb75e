// readPly and readPlyFromMemory on small well-formed files: every format, type and property name
// the reader maps, read back to the exact values written (large files and PlyChunkReader:
// test_ply_reader_large.cpp; malformed input: test_ply_reader_errors.cpp).
#include "io/ply_reader.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cfloat>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/ply_test_files.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::colors;
using test::expectFirstMismatch;
using test::expectSamePoints;
using test::expectScalarValues;
using test::kAllPlyFormats;
using test::normals;
using test::PlyBody;
using test::plyHeader;
using test::positionFile;
using test::readPlyText;
using test::scalarNames;
using test::scalarValues;
using test::World;
using test::worldPositions;

// ---------------------------------------------------------------------------------------------
// Formats

// Three points with positions, colours, normals, intensity, classification and one extra.
std::string mixedFile(PlyFormat format) {
  std::string header =
      plyHeader(format, {"element vertex 3", "property float x", "property float y",
                         "property float z", "property uchar red", "property uchar green",
                         "property uchar blue", "property float nx", "property float ny",
                         "property float nz", "property ushort intensity",
                         "property uchar classification", "property int quality"});
  PlyBody body(format);
  body.put(1.5f).put(-2.25f).put(0.125f).put<std::uint8_t>(255).put<std::uint8_t>(0);
  body.put<std::uint8_t>(7).put(0.0f).put(0.6f).put(0.8f).put<std::uint16_t>(65535);
  body.put<std::uint8_t>(2).put<std::int32_t>(-5).end();
  body.put(100.0f).put(200.5f).put(-300.75f).put<std::uint8_t>(1).put<std::uint8_t>(2);
  body.put<std::uint8_t>(3).put(1.0f).put(0.0f).put(0.0f).put<std::uint16_t>(0);
  body.put<std::uint8_t>(6).put<std::int32_t>(2147483647).end();
  body.put(0.0f).put(0.0f).put(0.0f).put<std::uint8_t>(10).put<std::uint8_t>(20);
  body.put<std::uint8_t>(30).put(-0.5f).put(-0.5f).put(-0.5f).put<std::uint16_t>(1000);
  body.put<std::uint8_t>(255).put<std::int32_t>(0).end();
  return header + body.bytes();
}

void expectMixedValues(const PointCloud& cloud) {
  ASSERT_EQ(cloud.count, 3u);
  EXPECT_EQ(worldPositions(cloud),
            (std::vector<World>{{1.5, -2.25, 0.125}, {100.0, 200.5, -300.75}, {0, 0, 0}}));
  EXPECT_EQ(colors(cloud),
            (std::vector<Rgba8>{{255, 0, 7, 255}, {1, 2, 3, 255}, {10, 20, 30, 255}}));
  EXPECT_EQ(normals(cloud),
            (std::vector<Float3>{{0.0f, 0.6f, 0.8f}, {1.0f, 0.0f, 0.0f}, {-0.5f, -0.5f, -0.5f}}));
  EXPECT_EQ(std::vector<float>(cloud.intensity.begin(), cloud.intensity.end()),
            (std::vector<float>{65535.0f, 0.0f, 1000.0f}));
  EXPECT_EQ(std::vector<std::uint8_t>(cloud.classification.begin(), cloud.classification.end()),
            (std::vector<std::uint8_t>{2, 6, 255}));
  EXPECT_EQ(scalarNames(cloud), (std::vector<std::string>{"quality"}));
  EXPECT_EQ(scalarValues<std::int32_t>(cloud, "quality", ScalarType::Int32),
            (std::vector<std::int32_t>{-5, 2147483647, 0}));
  EXPECT_EQ(cloud.source.position, ScalarType::Float32);
  EXPECT_EQ(cloud.source.color, ScalarType::UInt8);
  EXPECT_EQ(cloud.source.normal, ScalarType::Float32);
  EXPECT_EQ(cloud.source.intensity, ScalarType::UInt16);
  EXPECT_EQ(cloud.source.classification, ScalarType::UInt8);
  EXPECT_FALSE(cloud.source.has_alpha);
}

TEST(PlyReader, ReadsTheSameValuesFromEveryFormat) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    expectMixedValues(readPlyText(mixedFile(format)));
    expectMixedValues(readPlyText(mixedFile(format), /*parallel=*/false));
  }
}

TEST(PlyReader, ReadsFromAFileAsFromMemory) {
  test::TempDir dir;
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    auto path = dir.write("mixed_" + test::formatKeyword(format) + ".ply", mixedFile(format));
    PointCloud cloud = readPly(path);
    expectMixedValues(cloud);
  }
}

TEST(PlyReader, BoundsAreThoseOfThePointsRead) {
  PointCloud cloud = readPlyText(mixedFile(PlyFormat::BinaryLittleEndian));
  EXPECT_EQ(cloud.bounds.min, (World{0.0, -2.25, -300.75}));
  EXPECT_EQ(cloud.bounds.max, (World{100.0, 200.5, 0.125}));
}

TEST(PlyReader, AttributeNamesFollowTheModel) {
  PointCloud cloud = readPlyText(mixedFile(PlyFormat::Ascii));
  EXPECT_EQ(cloud.attributeNames(),
            (std::vector<std::string>{"x", "y", "z", "red", "green", "blue", "nx", "ny", "nz",
                                      "intensity", "classification", "quality"}));
}

TEST(PlyReader, ProgressAdvancesByThePointsRead) {
  struct Counter : Progress {
    std::atomic<std::uint64_t> total{0};
    void advance(std::uint64_t amount) override { total += amount; }
  };
  for (bool parallel : {false, true}) {
    Counter counter;
    PlyReadOptions options;
    options.parallel = parallel;
    options.progress = &counter;
    std::string file = mixedFile(PlyFormat::BinaryBigEndian);
    readPlyFromMemory(asBytes(file), "test.ply", options);
    EXPECT_EQ(counter.total.load(), 3u);
  }
}

// ---------------------------------------------------------------------------------------------
// Positions

TEST(PlyReader, FloatPositionsAreExact) {
  std::vector<World> points = {{1.5, -2.25, 1024.125}, {0.0, 3.0e4, -0.0078125}, {-7.75, 1, 2}};
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud = readPlyText(positionFile(format, "float", points));
    EXPECT_EQ(worldPositions(cloud), points);
    EXPECT_EQ(cloud.source.position, ScalarType::Float32);
  }
}

TEST(PlyReader, DoublePositionsAreExact) {
  std::vector<World> points = {{596732.4375, 4200000.125, 12.75},
                               {596800.0625, 4200100.5, -3.5},
                               {596750.0, 4200050.25, 100.0}};
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud = readPlyText(positionFile(format, "double", points));
    EXPECT_EQ(worldPositions(cloud), points);
    EXPECT_EQ(cloud.source.position, ScalarType::Float64);
  }
}

TEST(PlyReader, UtmDoubleCoordinatesKeepExactValuesAsFloat64Alias) {
  std::vector<World> points = {{596732.4375, 4200000.125, 0.5}};
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud = readPlyText(positionFile(format, "float64", points));
    ASSERT_EQ(cloud.count, 1u);
    EXPECT_EQ(cloud.worldX(0), 596732.4375);
    EXPECT_EQ(cloud.worldY(0), 4200000.125);
    EXPECT_EQ(cloud.worldZ(0), 0.5);
  }
}

TEST(PlyReader, IntegerPositionsAreExact) {
  struct Case {
    std::string type;
    ScalarType scalar;
    std::vector<World> points;
  };
  const Case cases[] = {
      {"char", ScalarType::Int8, {{-128, 127, 0}, {5, -5, 100}}},
      {"uchar", ScalarType::UInt8, {{0, 255, 17}, {255, 0, 1}}},
      {"short", ScalarType::Int16, {{-32768, 32767, 5}, {0, -1, 1}}},
      {"ushort", ScalarType::UInt16, {{0, 65535, 3}, {65535, 1, 0}}},
      {"int", ScalarType::Int32, {{-1000000, 1000001, 3}, {0, 7, -7}}},
      {"uint",
       ScalarType::UInt32,
       {{4000000000, 4000000001, 4000000123}, {4000000077, 4000000000, 4000000001}}},
      {"int32", ScalarType::Int32, {{596732, 4200000, -12}, {596733, 4200001, 0}}},
  };
  for (const Case& c : cases) {
    for (PlyFormat format : kAllPlyFormats) {
      SCOPED_TRACE(c.type + " " + test::formatKeyword(format));
      PointCloud cloud = readPlyText(positionFile(format, c.type, c.points));
      EXPECT_EQ(worldPositions(cloud), c.points);
      EXPECT_EQ(cloud.source.position, c.scalar);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Scalar properties

// One property per type with its extremes; `names` are the type names used in the header.
void putEveryTypeRecords(PlyBody& body);

// The three records are written `repeat` times.
std::string everyTypeFile(PlyFormat format, const std::array<std::string, 8>& names,
                          std::size_t repeat = 1) {
  std::string header = plyHeader(format, {});
  std::string lines = "element vertex " + std::to_string(3 * repeat) +
                      "\nproperty float x\nproperty float y\nproperty float z\n";
  const char* props[] = {"p_char", "p_uchar", "p_short", "p_ushort",
                         "p_int",  "p_uint",  "p_float", "p_double"};
  for (int i = 0; i < 8; ++i) lines += "property " + names[i] + " " + props[i] + "\n";
  header.insert(header.find("end_header"), lines);
  PlyBody body(format);
  for (std::size_t r = 0; r < repeat; ++r) putEveryTypeRecords(body);
  return header + body.bytes();
}

void putEveryTypeRecords(PlyBody& body) {
  body.put(1.0f).put(2.0f).put(3.0f);
  body.put<std::int8_t>(-128).put<std::uint8_t>(0).put<std::int16_t>(-32768);
  body.put<std::uint16_t>(0).put<std::int32_t>(std::numeric_limits<std::int32_t>::min());
  body.put<std::uint32_t>(0).put(-3.5f).put(-1.0e300).end();
  body.put(4.0f).put(5.0f).put(6.0f);
  body.put<std::int8_t>(127).put<std::uint8_t>(255).put<std::int16_t>(32767);
  body.put<std::uint16_t>(65535).put<std::int32_t>(2147483647);
  body.put<std::uint32_t>(4294967295u).put(FLT_MAX).put(596732.4375).end();
  body.put(7.0f).put(8.0f).put(9.0f);
  body.put<std::int8_t>(-1).put<std::uint8_t>(1).put<std::int16_t>(-2);
  body.put<std::uint16_t>(12345).put<std::int32_t>(7);
  body.put<std::uint32_t>(3000000000u).put(0.15625f).put(0.1).end();
}

// `values` written `times` times over.
template <class T>
std::vector<T> repeated(std::vector<T> values, std::size_t times) {
  std::vector<T> out;
  for (std::size_t r = 0; r < times; ++r) out.insert(out.end(), values.begin(), values.end());
  return out;
}

void expectEveryTypeValues(const PointCloud& cloud, std::size_t repeat = 1) {
  ASSERT_EQ(cloud.count, 3u * repeat);
  EXPECT_EQ(scalarNames(cloud),
            (std::vector<std::string>{"p_char", "p_uchar", "p_short", "p_ushort", "p_int", "p_uint",
                                      "p_float", "p_double"}));
  expectScalarValues<std::int8_t>(cloud, "p_char", ScalarType::Int8,
                                  repeated(std::vector<std::int8_t>{-128, 127, -1}, repeat));
  expectScalarValues<std::uint8_t>(cloud, "p_uchar", ScalarType::UInt8,
                                   repeated(std::vector<std::uint8_t>{0, 255, 1}, repeat));
  expectScalarValues<std::int16_t>(cloud, "p_short", ScalarType::Int16,
                                   repeated(std::vector<std::int16_t>{-32768, 32767, -2}, repeat));
  expectScalarValues<std::uint16_t>(cloud, "p_ushort", ScalarType::UInt16,
                                    repeated(std::vector<std::uint16_t>{0, 65535, 12345}, repeat));
  expectScalarValues<std::int32_t>(
      cloud, "p_int", ScalarType::Int32,
      repeated(std::vector<std::int32_t>{std::numeric_limits<std::int32_t>::min(), 2147483647, 7},
               repeat));
  expectScalarValues<std::uint32_t>(
      cloud, "p_uint", ScalarType::UInt32,
      repeated(std::vector<std::uint32_t>{0, 4294967295u, 3000000000u}, repeat));
  expectScalarValues<float>(cloud, "p_float", ScalarType::Float32,
                            repeated(std::vector<float>{-3.5f, FLT_MAX, 0.15625f}, repeat));
  expectScalarValues<double>(cloud, "p_double", ScalarType::Float64,
                             repeated(std::vector<double>{-1.0e300, 596732.4375, 0.1}, repeat));
  expectFirstMismatch(worldPositions(cloud),
                      repeated(std::vector<World>{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}, repeat),
                      "positions");
}

TEST(PlyReader, EveryScalarTypeIsKeptExactlyAsAScalarColumn) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    expectEveryTypeValues(readPlyText(everyTypeFile(
        format, {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"})));
  }
}

TEST(PlyReader, SizedTypeAliasesGiveTheSameColumns) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    expectEveryTypeValues(readPlyText(everyTypeFile(
        format, {"int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"})));
  }
}

TEST(PlyReaderLarge, EveryScalarTypeParallelEqualsSerial) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = everyTypeFile(
        format, {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"}, 40'000);
    PointCloud parallel = readPlyText(file, true);
    expectEveryTypeValues(parallel, 40'000);
    expectSamePoints(parallel, readPlyText(file, false));
  }
}

TEST(PlyReader, ScalarValueAsDoubleReadsEveryType) {
  PointCloud cloud =
      readPlyText(everyTypeFile(PlyFormat::BinaryBigEndian, {"char", "uchar", "short", "ushort",
                                                             "int", "uint", "float", "double"}));
  ASSERT_EQ(cloud.scalars.size(), 8u);
  EXPECT_EQ(cloud.findScalar("p_char")->valueAsDouble(0), -128.0);
  EXPECT_EQ(cloud.findScalar("p_uint")->valueAsDouble(1), 4294967295.0);
  EXPECT_EQ(cloud.findScalar("p_double")->valueAsDouble(1), 596732.4375);
}

// ---------------------------------------------------------------------------------------------
// Colours

// Two points at (0,0,0) and (1,1,1) with the given colour properties and per-point values.
std::string colorFile(PlyFormat format, const std::string& type,
                      const std::vector<std::string>& names,
                      const std::vector<std::vector<double>>& values) {
  std::string header = plyHeader(format, {});
  std::string lines = "element vertex " + std::to_string(values.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\n";
  for (const std::string& name : names) lines += "property " + type + " " + name + "\n";
  header.insert(header.find("end_header"), lines);
  ScalarType scalar = *parseScalarType(type);
  PlyBody body(format);
  float coordinate = 0;
  for (const auto& point : values) {
    body.put(coordinate).put(coordinate).put(coordinate);
    for (double v : point) body.put(scalar, v);
    body.end();
    coordinate += 1;
  }
  return header + body.bytes();
}

TEST(PlyReaderColors, UcharRedGreenBlueWithoutAlphaGetOpaqueAlpha) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud = readPlyText(
        colorFile(format, "uchar", {"red", "green", "blue"}, {{255, 128, 0}, {1, 2, 3}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 128, 0, 255}, {1, 2, 3, 255}}));
    EXPECT_FALSE(cloud.source.has_alpha);
    EXPECT_EQ(cloud.source.color, ScalarType::UInt8);
    EXPECT_TRUE(cloud.scalars.empty());
  }
}

TEST(PlyReaderColors, AlphaIsRead) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud = readPlyText(colorFile(format, "uint8", {"red", "green", "blue", "alpha"},
                                             {{10, 20, 30, 0}, {40, 50, 60, 77}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{10, 20, 30, 0}, {40, 50, 60, 77}}));
    EXPECT_TRUE(cloud.source.has_alpha);
    EXPECT_TRUE(cloud.scalars.empty());
  }
}

TEST(PlyReaderColors, ShortNamesRGBA) {
  PointCloud rgb = readPlyText(
      colorFile(PlyFormat::BinaryLittleEndian, "uchar", {"r", "g", "b"}, {{9, 8, 7}, {6, 5, 4}}));
  EXPECT_EQ(colors(rgb), (std::vector<Rgba8>{{9, 8, 7, 255}, {6, 5, 4, 255}}));
  EXPECT_TRUE(rgb.scalars.empty());
  PointCloud rgba = readPlyText(
      colorFile(PlyFormat::Ascii, "uchar", {"r", "g", "b", "a"}, {{9, 8, 7, 6}, {6, 5, 4, 3}}));
  EXPECT_EQ(colors(rgba), (std::vector<Rgba8>{{9, 8, 7, 6}, {6, 5, 4, 3}}));
  EXPECT_TRUE(rgba.source.has_alpha);
}

TEST(PlyReaderColors, DiffuseNames) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud =
        readPlyText(colorFile(format, "uchar", {"diffuse_red", "diffuse_green", "diffuse_blue"},
                              {{200, 100, 50}, {0, 255, 1}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{200, 100, 50, 255}, {0, 255, 1, 255}}));
    EXPECT_TRUE(cloud.scalars.empty());
  }
}

TEST(PlyReaderColors, UshortColorsAreScaledTo8Bits) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud cloud =
        readPlyText(colorFile(format, "ushort", {"red", "green", "blue", "alpha"},
                              {{65535, 0, 257, 257 * 128}, {257 * 200, 65535, 0, 65535}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 0, 1, 128}, {200, 255, 0, 255}}));
    EXPECT_EQ(cloud.source.color, ScalarType::UInt16);
    EXPECT_TRUE(cloud.source.has_alpha);
  }
}

TEST(PlyReaderColors, FloatColorsAreScaledFromZeroToOne) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    // 0.25 * 255 = 63.75 rounds to 64 (a truncating reader would give 63); 0.5 * 255 = 127.5
    // rounds to 128 both half-away and half-to-even.
    PointCloud cloud = readPlyText(
        colorFile(format, "float", {"red", "green", "blue"}, {{1.0, 0.0, 0.5}, {0.25, 0.2, 0.75}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 0, 128, 255}, {64, 51, 191, 255}}));
    EXPECT_EQ(cloud.source.color, ScalarType::Float32);
    EXPECT_FALSE(cloud.source.has_alpha);
  }
}

TEST(PlyReaderColors, DoubleColorsWithAlphaAreScaled) {
  PointCloud cloud =
      readPlyText(colorFile(PlyFormat::BinaryBigEndian, "double", {"red", "green", "blue", "alpha"},
                            {{1.0, 0.0, 0.5, 0.25}}));
  EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 0, 128, 64}}));
  EXPECT_EQ(cloud.source.color, ScalarType::Float64);
}

// Assumption (not in the header): float colours outside 0..1 are clamped, never wrapped.
TEST(PlyReaderColors, FloatColorsOutsideZeroToOneAreClamped) {
  PointCloud cloud = readPlyText(colorFile(PlyFormat::BinaryLittleEndian, "float",
                                           {"red", "green", "blue"}, {{1.5, -0.5, 2.0}}));
  EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 0, 255, 255}}));
}

TEST(PlyReaderColors, NoColorPropertiesNoColorColumn) {
  PointCloud cloud = readPlyText(positionFile(PlyFormat::Ascii, "float", {{1, 2, 3}}));
  EXPECT_FALSE(cloud.hasColors());
  EXPECT_FALSE(cloud.hasNormals());
  EXPECT_FALSE(cloud.hasIntensity());
  EXPECT_FALSE(cloud.hasClassification());
  EXPECT_TRUE(cloud.scalars.empty());
}

// ---------------------------------------------------------------------------------------------
// Normals, intensity, classification

TEST(PlyReader, NormalsUnderBothNames) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud short_names = readPlyText(
        colorFile(format, "float", {"nx", "ny", "nz"}, {{0.0, 0.6, 0.8}, {-1.0, 0.0, 0.0}}));
    EXPECT_EQ(normals(short_names), (std::vector<Float3>{{0.0f, 0.6f, 0.8f}, {-1.0f, 0.0f, 0.0f}}));
    EXPECT_FALSE(short_names.hasColors());
    EXPECT_TRUE(short_names.scalars.empty());

    PointCloud long_names =
        readPlyText(colorFile(format, "double", {"normal_x", "normal_y", "normal_z"},
                              {{0.0, 0.6, 0.8}, {0.5, -0.5, 0.25}}));
    EXPECT_EQ(normals(long_names), (std::vector<Float3>{{0.0f, 0.6f, 0.8f}, {0.5f, -0.5f, 0.25f}}));
    EXPECT_EQ(long_names.source.normal, ScalarType::Float64);
    EXPECT_TRUE(long_names.scalars.empty());
  }
}

TEST(PlyReader, IntensityUnderBothNames) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud plain = readPlyText(colorFile(format, "float", {"intensity"}, {{0.25}, {1500.5}}));
    EXPECT_EQ(std::vector<float>(plain.intensity.begin(), plain.intensity.end()),
              (std::vector<float>{0.25f, 1500.5f}));
    EXPECT_EQ(plain.source.intensity, ScalarType::Float32);
    PointCloud scalar =
        readPlyText(colorFile(format, "ushort", {"scalar_intensity"}, {{65535}, {0}}));
    EXPECT_EQ(std::vector<float>(scalar.intensity.begin(), scalar.intensity.end()),
              (std::vector<float>{65535.0f, 0.0f}));
    EXPECT_EQ(scalar.source.intensity, ScalarType::UInt16);
    EXPECT_TRUE(scalar.scalars.empty());
  }
}

TEST(PlyReader, ClassificationUnderBothNames) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PointCloud plain = readPlyText(colorFile(format, "uchar", {"classification"}, {{2}, {255}}));
    EXPECT_EQ(std::vector<std::uint8_t>(plain.classification.begin(), plain.classification.end()),
              (std::vector<std::uint8_t>{2, 255}));
    PointCloud scalar =
        readPlyText(colorFile(format, "uchar", {"scalar_classification"}, {{6}, {0}}));
    EXPECT_EQ(std::vector<std::uint8_t>(scalar.classification.begin(), scalar.classification.end()),
              (std::vector<std::uint8_t>{6, 0}));
    EXPECT_TRUE(scalar.scalars.empty());
  }
}

// ---------------------------------------------------------------------------------------------
// Property order, unknown properties, lists

TEST(PlyReader, PropertiesInAnyOrder) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header =
        plyHeader(format, {"element vertex 2", "property double z", "property ushort confidence",
                           "property float x", "property uchar blue", "property uchar red",
                           "property uchar green", "property float y", "property float nz",
                           "property short label", "property float nx", "property float ny"});
    PlyBody body(format);
    body.put(3.5).put<std::uint16_t>(40000).put(1.5f).put<std::uint8_t>(30);
    body.put<std::uint8_t>(10).put<std::uint8_t>(20).put(2.5f).put(1.0f);
    body.put<std::int16_t>(-300).put(0.0f).put(0.0f).end();
    body.put(-6.0).put<std::uint16_t>(1).put(-4.0f).put<std::uint8_t>(3);
    body.put<std::uint8_t>(1).put<std::uint8_t>(2).put(-5.0f).put(0.0f);
    body.put<std::int16_t>(7).put(0.0f).put(-1.0f).end();
    PointCloud cloud = readPlyText(header + body.bytes());
    EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1.5, 2.5, 3.5}, {-4, -5, -6}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{10, 20, 30, 255}, {1, 2, 3, 255}}));
    EXPECT_EQ(normals(cloud), (std::vector<Float3>{{0, 0, 1}, {0, -1, 0}}));
    EXPECT_EQ(scalarNames(cloud), (std::vector<std::string>{"confidence", "label"}));
    EXPECT_EQ(scalarValues<std::uint16_t>(cloud, "confidence", ScalarType::UInt16),
              (std::vector<std::uint16_t>{40000, 1}));
    EXPECT_EQ(scalarValues<std::int16_t>(cloud, "label", ScalarType::Int16),
              (std::vector<std::int16_t>{-300, 7}));
  }
}

// x, list<uchar,int> ids, y, list<uint,float> weights, z, list<short,double> extra, colour:
// lists of lengths 0, 3, 1 and 2, 0, 4 and 1, 0, 2, with values that would shift every later
// field if a list were misread.
std::string vertexListFile(PlyFormat format) {
  std::string header =
      plyHeader(format, {"element vertex 3", "property float x", "property list uchar int ids",
                         "property float y", "property list uint float weights", "property float z",
                         "property list short double extra", "property uchar red",
                         "property uchar green", "property uchar blue"});
  PlyBody body(format);
  body.put(1.0f).put<std::uint8_t>(0).put(2.0f).put<std::uint32_t>(2).put(9.5f).put(9.25f);
  body.put(3.0f).put<std::int16_t>(1).put(-0.5).put<std::uint8_t>(1).put<std::uint8_t>(2);
  body.put<std::uint8_t>(3).end();
  body.put(4.0f).put<std::uint8_t>(3).put<std::int32_t>(-1).put<std::int32_t>(65536);
  body.put<std::int32_t>(7).put(5.0f).put<std::uint32_t>(0).put(6.0f).put<std::int16_t>(0);
  body.put<std::uint8_t>(4);
  body.put<std::uint8_t>(5).put<std::uint8_t>(6).end();
  body.put(7.0f).put<std::uint8_t>(1).put<std::int32_t>(100).put(8.0f).put<std::uint32_t>(4);
  body.put(1.0f).put(2.0f).put(3.0f).put(4.0f).put(9.0f).put<std::int16_t>(2).put(1.0e300);
  body.put(-2.0).put<std::uint8_t>(7);
  body.put<std::uint8_t>(8).put<std::uint8_t>(9).end();
  return header + body.bytes();
}

void expectVertexListValues(const PointCloud& cloud) {
  ASSERT_EQ(cloud.count, 3u);
  EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}));
  EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{1, 2, 3, 255}, {4, 5, 6, 255}, {7, 8, 9, 255}}));
  EXPECT_TRUE(cloud.scalars.empty()) << "list properties must not become scalar columns";
}

TEST(PlyReader, ListPropertiesOfTheVertexElementAreSkipped) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    expectVertexListValues(readPlyText(vertexListFile(format)));
    expectVertexListValues(readPlyText(vertexListFile(format), /*parallel=*/false));
  }
}

// ---------------------------------------------------------------------------------------------
// Several elements

// vertex_indices lists of lengths 3 and 4 (uchar count, int items) and a flags byte.
void putFaces(PlyBody& body) {
  body.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
  body.put<std::uint8_t>(1).end();
  body.put<std::uint8_t>(4).put<std::int32_t>(0).put<std::int32_t>(2).put<std::int32_t>(3);
  body.put<std::int32_t>(1).put<std::uint8_t>(0).end();
}

void putVertices(PlyBody& body) {
  body.put(0.5f).put(1.5f).put(2.5f).end();
  body.put(-0.5f).put(-1.5f).put(-2.5f).end();
  body.put(10.0f).put(20.0f).put(30.0f).end();
  body.put(0.0f).put(0.0f).put(1.0f).end();
}

const std::vector<World> kMeshVertices = {
    {0.5, 1.5, 2.5}, {-0.5, -1.5, -2.5}, {10, 20, 30}, {0, 0, 1}};

TEST(PlyReader, MeshWithFacesAfterVertices) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header =
        plyHeader(format, {"element vertex 4", "property float x", "property float y",
                           "property float z", "element face 2",
                           "property list uchar int vertex_indices", "property uchar flags"});
    PlyBody body(format);
    putVertices(body);
    putFaces(body);
    PointCloud cloud = readPlyText(header + body.bytes());
    EXPECT_EQ(worldPositions(cloud), kMeshVertices);
    EXPECT_TRUE(cloud.scalars.empty());
  }
}

TEST(PlyReader, FacesAndCameraBeforeVertices) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header = plyHeader(
        format, {"element camera 1", "property float view_px", "property double view_py",
                 "property uint viewport_w", "property list uint uchar tags", "element face 2",
                 "property list uchar int vertex_indices", "property uchar flags",
                 "element vertex 4", "property float x", "property float y", "property float z",
                 "element edge 1", "property int vertex1", "property int vertex2"});
    PlyBody body(format);
    body.put(1.25f).put(-8.5).put<std::uint32_t>(1920).put<std::uint32_t>(2);
    body.put<std::uint8_t>(255).put<std::uint8_t>(10).end();
    putFaces(body);
    putVertices(body);
    body.put<std::int32_t>(0).put<std::int32_t>(3).end();
    for (bool parallel : {true, false}) {
      PointCloud cloud = readPlyText(header + body.bytes(), parallel);
      EXPECT_EQ(worldPositions(cloud), kMeshVertices);
      EXPECT_TRUE(cloud.scalars.empty()) << "properties of other elements are not points'";
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Header and ascii layout variants

TEST(PlyReader, CommentsAndObjInfoAnywhereInTheHeader) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header =
        plyHeader(format, {"comment Generated by a test", "obj_info num_cols 2", "element vertex 2",
                           "comment between element and property", "property float x",
                           "obj_info between properties", "property float y", "property float z",
                           "comment last"});
    PlyBody body(format);
    body.put(1.0f).put(2.0f).put(3.0f).end().put(4.0f).put(5.0f).put(6.0f).end();
    PointCloud cloud = readPlyText(header + body.bytes());
    EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1, 2, 3}, {4, 5, 6}}));
  }
}

TEST(PlyReader, CrlfLineEndsInHeaderAndAsciiBody) {
  std::string header = plyHeader(
      PlyFormat::Ascii,
      {"comment windows", "element vertex 2", "property float x", "property float y",
       "property float z", "property uchar red", "property uchar green", "property uchar blue"},
      "\r\n");
  PlyBody body(PlyFormat::Ascii);
  body.put(1.5f).put(2.5f).put(3.5f).put<std::uint8_t>(1).put<std::uint8_t>(2);
  body.put<std::uint8_t>(3).end("\r\n");
  body.put(4.0f).put(5.0f).put(6.0f).put<std::uint8_t>(4).put<std::uint8_t>(5);
  body.put<std::uint8_t>(255).end("\r\n");
  for (bool parallel : {true, false}) {
    PointCloud cloud = readPlyText(header + body.bytes(), parallel);
    EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1.5, 2.5, 3.5}, {4, 5, 6}}));
    EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{1, 2, 3, 255}, {4, 5, 255, 255}}));
  }
}

TEST(PlyReader, CrlfHeaderBeforeABinaryBody) {
  std::string header = plyHeader(
      PlyFormat::BinaryLittleEndian,
      {"element vertex 1", "property float x", "property float y", "property float z"}, "\r\n");
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f);
  PointCloud cloud = readPlyText(header + body.bytes());
  EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1, 2, 3}}));
}

TEST(PlyReader, ExtraSpacesAndTabsInAsciiBody) {
  std::string header =
      plyHeader(PlyFormat::Ascii, {"element vertex 3", "property float x", "property float y",
                                   "property float z", "property list uchar int ids"});
  std::string body =
      "  1.5\t-2 \t 3  2 7\t8\n"
      "\t4 5 6 0 \t\n"
      "7   8\t\t9 1   -3   \n";
  for (bool parallel : {true, false}) {
    PointCloud cloud = readPlyText(header + body, parallel);
    EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1.5, -2, 3}, {4, 5, 6}, {7, 8, 9}}));
  }
}

TEST(PlyReader, AsciiTrailingBlankLineAndMissingLastLineEnd) {
  std::string header = plyHeader(PlyFormat::Ascii, {"element vertex 2", "property float x",
                                                    "property float y", "property float z"});
  PointCloud trailing_blank = readPlyText(header + "1 2 3\n4 5 6\n\n");
  PointCloud trailing_whitespace = readPlyText(header + "1 2 3\n4 5 6\n \t\r\n\n");
  EXPECT_EQ(worldPositions(trailing_whitespace), (std::vector<World>{{1, 2, 3}, {4, 5, 6}}));
  EXPECT_EQ(worldPositions(trailing_blank), (std::vector<World>{{1, 2, 3}, {4, 5, 6}}));
  PointCloud no_last_eol = readPlyText(header + "1 2 3\n4 5 6");
  EXPECT_EQ(worldPositions(no_last_eol), (std::vector<World>{{1, 2, 3}, {4, 5, 6}}));
}

TEST(PlyReader, AsciiNumberSpellings) {
  // Exponents, integers written for float properties, a negative zero for an integer, bare
  // leading or trailing points, leading zeros, and mantissas longer than a double holds.
  std::string header =
      plyHeader(PlyFormat::Ascii, {"element vertex 4", "property float x", "property double y",
                                   "property double z", "property int count"});
  PointCloud cloud = readPlyText(header +
                                 "1.5e2 -2.5E-1 3 12\n"
                                 "7 596732.4375 0.125 -0\n"
                                 ".5 5. -.25 007\n"
                                 "1E1 596732.437500000000000001 4200000.1250000000000000001 1\n");
  EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{150, -0.25, 3},
                                                       {7, 596732.4375, 0.125},
                                                       {0.5, 5, -0.25},
                                                       {10, 596732.4375, 4200000.125}}));
  EXPECT_EQ(scalarValues<std::int32_t>(cloud, "count", ScalarType::Int32),
            (std::vector<std::int32_t>{12, 0, 7, 1}));
}

// C's strtod and strtol, which the reference PLY library reads with, accept a leading '+'.
TEST(PlyReader, AsciiLeadingPlusSign) {
  std::string header =
      plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property double y",
                                   "property float z", "property int count"});
  PointCloud cloud = readPlyText(header + "+1.5 +2 +0.25e1 +12\n");
  EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1.5, 2, 2.5}}));
  EXPECT_EQ(scalarValues<std::int32_t>(cloud, "count", ScalarType::Int32),
            (std::vector<std::int32_t>{12}));
}

// Writers print floats with the shortest text that reads back to the same float (printf %.9g,
// std::to_chars); reading that text as float must give the float back, extremes included.
TEST(PlyReader, AsciiFloatExtremesReadBackExactly) {
  const float values[] = {FLT_MAX, -FLT_MAX, FLT_MIN, 1.0e-45f, 16777216.0f};
  std::string header =
      plyHeader(PlyFormat::Ascii, {"element vertex 5", "property float x", "property float y",
                                   "property float z", "property float value"});
  PlyBody body(PlyFormat::Ascii);
  for (float value : values) body.put(0.0f).put(0.0f).put(0.0f).put(value).end();
  PointCloud cloud = readPlyText(header + body.bytes());
  EXPECT_EQ(scalarValues<float>(cloud, "value", ScalarType::Float32),
            (std::vector<float>(std::begin(values), std::end(values))));
}

// Some writers print every value as a float, integers included ("255.000000"): a whole number
// is accepted for an integer property (a fraction is an error, see the error tests).
TEST(PlyReader, AsciiWholeNumbersWrittenAsFloatsForIntegerProperties) {
  std::string header =
      plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property float y",
                                   "property float z", "property uchar red", "property uchar green",
                                   "property uchar blue", "property uint id"});
  PointCloud cloud = readPlyText(header + "1 2 3 255.000000 0.0 1.28e2 4294967295.0\n");
  EXPECT_EQ(colors(cloud), (std::vector<Rgba8>{{255, 0, 128, 255}}));
  EXPECT_EQ(scalarValues<std::uint32_t>(cloud, "id", ScalarType::UInt32),
            (std::vector<std::uint32_t>{4294967295u}));
}

TEST(PlyReader, EmptyVertexElement) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header =
        plyHeader(format, {"element vertex 0", "property float x", "property float y",
                           "property float z", "property uchar red", "property uchar green",
                           "property uchar blue", "property ushort quality"});
    PointCloud cloud = readPlyText(header);
    EXPECT_EQ(cloud.count, 0u);
    EXPECT_EQ(cloud.positions.size(), 0u);
    EXPECT_EQ(cloud.colors.size(), 0u);
    EXPECT_TRUE(cloud.bounds.empty());
    for (const ScalarColumn& column : cloud.scalars) EXPECT_EQ(column.data.size(), 0u);
  }
}

TEST(PlyReader, VertexElementUnderItsAliases) {
  for (std::string name : {"vertices", "point", "points"}) {
    SCOPED_TRACE(name);
    std::string element = "element " + name + " 1";
    std::string header = plyHeader(
        PlyFormat::Ascii, {element, "property float x", "property float y", "property float z"});
    PointCloud cloud = readPlyText(header + "1 2 3\n");
    EXPECT_EQ(worldPositions(cloud), (std::vector<World>{{1, 2, 3}}));
  }
}

}  // namespace
}  // namespace parallax
