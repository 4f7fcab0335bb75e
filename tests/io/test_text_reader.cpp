#include "io/text_reader.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>

#include "core/error.h"
#include "io/point_file.h"
#include "io/text_writer.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

PointCloud readString(const std::string& text, const std::string& name = "t.xyz",
                      const TextReadOptions& options = {}) {
  return readTextFromMemory({reinterpret_cast<const std::byte*>(text.data()), text.size()}, name,
                            options);
}

InputErrorInfo errorOf(const std::string& text, const TextReadOptions& options = {}) {
  try {
    readString(text, "t.xyz", options);
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "t.xyz");
    return e.info();
  }
  ADD_FAILURE() << "no error for " << text;
  return {};
}

TEST(TextReader, CommonLayoutByColumnCount) {
  PointCloud xyz = readString("1 2 3\n4 5 6\n");
  ASSERT_EQ(xyz.count, 2u);
  EXPECT_FALSE(xyz.hasColors());
  EXPECT_EQ(xyz.worldX(1), 4.0);

  PointCloud rgb = readString("1.5 2.25 3 255 128 0\r\n-1 -2 -3 1 2 3\r\n");
  ASSERT_TRUE(rgb.hasColors());
  EXPECT_EQ(rgb.colors[0], (Rgba8{255, 128, 0, 255}));
  EXPECT_EQ(rgb.worldY(0), 2.25);
  EXPECT_EQ(rgb.quantization.scale, (std::array<double, 3>{0.1, 0.01, 1.0}));

  PointCloud xyzi = readString("1 2 3 0.5\n");
  EXPECT_EQ(xyzi.intensity[0], 0.5f);

  PointCloud nine = readString("0 0 0 1 2 3 0 0 1\n");
  EXPECT_EQ(nine.normals[0], (Float3{0, 0, 1}));
}

TEST(TextReader, ASecondColumnForAModelColumnIsAScalar) {
  // A LAS file with an extra bytes field "Intensity" written to CSV has "intensity" and
  // "Intensity": names match in any case, so the second became intensity again and was lost.
  const PointCloud cloud = readString("x,y,z,intensity,Intensity\n1,2,3,10,20\n", "t.csv");
  ASSERT_EQ(cloud.count, 1u);
  EXPECT_EQ(cloud.intensity[0], 10.0f);
  const ScalarColumn* second = cloud.findScalar("Intensity");
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->valueAsDouble(0), 20.0);
}

TEST(TextReader, Open3dXyznAndXyzrgbLayouts) {
  // Lines as Open3D 0.16's write_point_cloud prints them ("%.10f"). Read as the common 6-column
  // layout, the normals of .xyzn were colours (rounded to 0 or 1) and the colours of .xyzrgb,
  // fractions of full scale, were rounded to 0 or 1.
  const std::string normals =
      "889.7968750000 250.1875000000 468.3593750000 0.3068979979 0.1421974748 -0.9410597682\n";
  const PointCloud xyzn = readString(normals, "cloud.xyzn");
  ASSERT_TRUE(xyzn.hasNormals());
  EXPECT_FALSE(xyzn.hasColors());
  EXPECT_EQ(xyzn.normals[0], (Float3{0.3068979979f, 0.1421974748f, -0.9410597682f}));
  EXPECT_EQ(xyzn.worldZ(0), 468.359375);

  // 112/255, 154/255, 1 and 0: Open3D's colours of (112, 154, 255) and (0, 0, 0).
  const PointCloud xyzrgb = readString(
      "1 2 3 0.4392156863 0.6039215686 1.0000000000\n4 5 6 0.0000000000 0.0000000000 "
      "0.0000000000\n",
      "cloud.xyzrgb");
  ASSERT_TRUE(xyzrgb.hasColors());
  EXPECT_EQ(xyzrgb.colors[0], (Rgba8{112, 154, 255, 255}));
  EXPECT_EQ(xyzrgb.colors[1], (Rgba8{0, 0, 0, 255}));
  // 0..255 integers under that extension stay as they are; other extensions keep the common
  // layout.
  EXPECT_EQ(readString("1 2 3 112 154 1\n", "cloud.xyzrgb").colors[0], (Rgba8{112, 154, 1, 255}));
  EXPECT_EQ(readString("1 2 3 0.4 0.6 1.0\n", "cloud.txt").colors[0], (Rgba8{0, 1, 1, 255}));
}

TEST(TextReader, CloudCompareSevenColumnsWithoutAHeader) {
  // CloudCompare 2.11's "-C_EXPORT_FMT ASC" without -ADD_HEADER, colours and one scalar field:
  // X Y Z R G B SF. Read in Leica's order (x y z intensity r g b) every value after z moved one
  // column: intensity 112 (the red), colour 154 114 226 (green, blue and the scalar rounded).
  const std::string cc =
      "889.796875000 250.187500000 468.359375000 112 154 114 225.625000000\n"
      "794.421875000 156.578125000 651.359375000 163 140 173 116.812500000\n";
  const PointCloud cloud = readString(cc, "cc.asc");
  ASSERT_TRUE(cloud.hasColors());
  EXPECT_EQ(cloud.colors[0], (Rgba8{112, 154, 114, 255}));
  EXPECT_EQ(cloud.colors[1], (Rgba8{163, 140, 173, 255}));
  EXPECT_EQ(cloud.intensity[1], 116.8125f);
  // Leica's order where column 4 is no colour value, or where both orders fit (all integers
  // 0..255), and always in a .pts file.
  EXPECT_EQ(readString("1 2 3 -1024 10 20 30\n", "t.txt").colors[0], (Rgba8{10, 20, 30, 255}));
  EXPECT_EQ(readString("1 2 3 7 10 20 30\n", "t.txt").intensity[0], 7.0f);
  EXPECT_EQ(readString("1\n1 2 3 7 10 20 30.5\n", "t.pts").intensity[0], 7.0f);
}

TEST(TextReader, PtsCountLineAndIntensityRgb) {
  PointCloud pts = readString("2\n1 2 3 -1024 10 20 30\n4 5 6 2047 40 50 60\n", "scan.pts");
  ASSERT_EQ(pts.count, 2u);
  EXPECT_EQ(pts.intensity[0], -1024.0f);
  EXPECT_EQ(pts.colors[1], (Rgba8{40, 50, 60, 255}));
  // Concatenated scans: further count lines are skipped.
  PointCloud two = readString("1\n1 2 3 5 1 1 1\n1\n4 5 6 5 1 1 1\n", "scan.pts");
  EXPECT_EQ(two.count, 2u);
  // A count line last, with nothing after it (found by the fuzzer: it must not be stored).
  EXPECT_EQ(readString("2\n1 2 0 \n5 ", "scan.pts", {.columns = {"x", "y", "z"}}).count, 1u);
  EXPECT_EQ(
      readString("1\n9 1 2 3\n7", "scan.pts", {.columns = {"intensity", "x", "y", "z"}}).count, 1u);
}

// A CR before a line's first value is a blank, for the line counter and the parser alike (found by
// the fuzzer: the counter took "\r0 1 2" for a point, the parser for a blank line, and the reader
// stopped on its own consistency check instead of reading the point).
TEST(TextReader, ACarriageReturnBeforeTheValuesIsABlank) {
  for (const char* name : {"t.xyz", "scan.pts"}) {
    SCOPED_TRACE(name);
    const PointCloud cloud =
        readString("\r0 1 2\n \r4 5 6\r\n", name, {.columns = {"x", "y", "z"}, .parallel = false});
    ASSERT_EQ(cloud.count, 2u);
    EXPECT_EQ(cloud.worldX(0), 0.0);
    EXPECT_EQ(cloud.worldZ(0), 2.0);
    EXPECT_EQ(cloud.worldX(1), 4.0);
    EXPECT_EQ(cloud.worldZ(1), 6.0);
  }
  // The fuzzer's input itself (PTS): the point 0 12012 30, then a blank line and a count line.
  const PointCloud fuzzed =
      readString("\r0 012012   30\n\n4", "scan.pts", {.parallel = false, .pts = true});
  ASSERT_EQ(fuzzed.count, 1u);
  EXPECT_EQ(fuzzed.worldY(0), 12012.0);
  EXPECT_EQ(fuzzed.worldZ(0), 30.0);
}

TEST(TextReader, HeaderLineNamesTheColumns) {
  PointCloud cloud = readString(
      "# exported\n// another comment\nX,Y,Z,intensity,gps_time,return_number,confidence\n"
      "1,2,3,100,1000.125,2,0.75\n\n4,5,6,200,1001.5,1,0.5\n");
  ASSERT_EQ(cloud.count, 2u);
  EXPECT_EQ(cloud.intensity[1], 200.0f);
  ASSERT_NE(cloud.findScalar("gps_time"), nullptr);
  EXPECT_EQ(cloud.findScalar("gps_time")->type, ScalarType::Float64);
  EXPECT_EQ(cloud.findScalar("gps_time")->as<double>()[0], 1000.125);
  EXPECT_EQ(cloud.findScalar("return_number")->type, ScalarType::UInt8);
  EXPECT_EQ(cloud.findScalar("confidence")->as<double>()[1], 0.5);
}

TEST(TextReader, SemicolonsAndCloudCompareCommentHeader) {
  PointCloud cloud = readString("//X;Y;Z;R;G;B\n1;2;3;4;5;6\n");
  EXPECT_EQ(cloud.colors[0], (Rgba8{4, 5, 6, 255}));
  PointCloud comma = readString("//X,Y,Z,Classification\n1.0, 2.0, 3.0, 7\n");
  EXPECT_EQ(comma.classification[0], 7);
}

TEST(TextReader, AlphaAloneStillMakesAColourColumn) {
  PointCloud cloud = readString("x y z a\n1 2 3 128\n");  // found by the fuzzer
  ASSERT_TRUE(cloud.hasColors());
  EXPECT_EQ(cloud.colors[0], (Rgba8{0, 0, 0, 128}));
}

TEST(TextReader, ColumnsOptionOverridesAndSkips) {
  PointCloud cloud = readString("x y z junk r g b\n9 1 2 3 4 5 6\n", "t.txt",
                                {.columns = {"_", "x", "y", "z", "r", "g", "b"}});
  EXPECT_EQ(cloud.worldX(0), 1.0);
  EXPECT_EQ(cloud.colors[0], (Rgba8{4, 5, 6, 255}));
}

TEST(TextReader, LargeCoordinatesAreExactToTheirDecimals) {
  std::string text;
  for (int i = 0; i < 20000; ++i) {
    text += std::to_string(512000 + i) + ".123 " + std::to_string(5400000 - i) + ".9 " +
            std::to_string(i % 100) + ".01\n";
  }
  PointCloud cloud = readString(text);
  ASSERT_EQ(cloud.count, 20000u);
  EXPECT_EQ(cloud.quantization.scale, (std::array<double, 3>{0.001, 0.1, 0.01}));
  EXPECT_DOUBLE_EQ(cloud.worldX(19999), 531999.123);
  EXPECT_DOUBLE_EQ(cloud.worldY(5), 5399995.9);
  EXPECT_DOUBLE_EQ(cloud.worldZ(123), 23.01);
}

TEST(TextReader, NumbersReadToTheSameBitsAsStrtod) {
  // The reader's own decimal fast path and fast_float must both give correctly rounded doubles.
  std::mt19937_64 rng(7);
  std::string text = "x y z v\n";
  std::vector<double> expected;
  for (int i = 0; i < 20000; ++i) {
    char buffer[64];
    int digits = int(rng() % 18) + 1;
    std::uint64_t mantissa = rng() % 1000000000000000000ull;
    std::string m = std::to_string(mantissa).substr(0, std::size_t(digits));
    std::size_t dot = rng() % (m.size() + 1);
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on a + chain here.
    std::string token = rng() % 2 ? "-" : "";
    token += m.substr(0, dot);
    token += '.';
    token += m.substr(dot);
    if (i % 7 == 0) {
      token += 'e';
      token += std::to_string(int(rng() % 40) - 20);
    }
    std::snprintf(buffer, sizeof buffer, "1 2 3 %s\n", token.c_str());
    text += buffer;
    expected.push_back(std::strtod(token.c_str(), nullptr));
  }
  PointCloud cloud = readString(text);
  const ScalarColumn* v = cloud.findScalar("v");
  ASSERT_NE(v, nullptr);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(v->as<double>()[i], expected[i]) << i;
  }
}

TEST(TextReader, BadLinesAreNamedByLineAndColumn) {
  auto info = errorOf("1 2 3\n4 5 6\n7 8\n");
  EXPECT_EQ(info.line, 3u);
  EXPECT_EQ(info.expected, "3 values");
  EXPECT_EQ(info.found, "2 values");

  info = errorOf("x y z\n1 2 3\n4 abc 6\n");
  EXPECT_EQ(info.line, 3u);
  EXPECT_EQ(info.property, "y");
  EXPECT_EQ(info.found, "'abc'");

  info = errorOf("1 2 3 4 5\n");
  EXPECT_EQ(info.line, 1u);
  EXPECT_NE(info.hint.find("--columns"), std::string::npos);

  info = errorOf("a b c\n1 2 3\n");
  EXPECT_NE(info.found.find("no x, y or z"), std::string::npos);

  info = errorOf("1 2 inf\n");
  EXPECT_EQ(info.property, "z");

  info = errorOf("");
  EXPECT_EQ(info.line, 1u);

  // An error deep in a large file names its line exactly (the parallel blocks).
  std::string big;
  for (int i = 0; i < 200000; ++i) big += "1.25 2.5 3.75\n";
  big += "1 2 x\n";
  info = errorOf(big);
  EXPECT_EQ(info.line, 200001u);
}

TEST(TextWriter, XyzHasAHeaderLineOnlyWhereTheReaderNeedsOne) {
  // Open3D 0.16's tensor reader refuses an .xyz file with a header line ("Read TXT failed at
  // line: x y z"): an .xyz whose columns the reader takes by their count is numbers only.
  test::TempDir dir;
  const PointCloud xyzrgb = readString("1.5 2 3 10 20 30\n4 5 6 40 50 60\n", "in.txt");
  const auto plain = dir / "plain.xyz";
  writeText(xyzrgb, plain, textOptionsForPath(plain));
  EXPECT_EQ(test::fileBytes(plain), "1.5 2 3 10 20 30\n4.0 5 6 40 50 60\n");
  const PointCloud back = readPointFile(plain);
  EXPECT_EQ(back.colors[1], (Rgba8{40, 50, 60, 255}));
  EXPECT_EQ(back.worldX(0), 1.5);
  // Other columns need the names; other extensions keep the header line.
  const PointCloud extra = readString("x y z temperature\n1 2 3 4\n", "in.txt");
  writeText(extra, plain, textOptionsForPath(plain));
  EXPECT_EQ(test::fileBytes(plain), "x y z temperature\n1 2 3 4\n");
  const auto txt = dir / "plain.txt";
  writeText(xyzrgb, txt, textOptionsForPath(txt));
  EXPECT_EQ(test::fileBytes(txt).substr(0, 21), "x y z red green blue\n");
}

TEST(TextReader, DetectedByContent) {
  test::TempDir dir;
  auto path = dir.write("points.dat", "# scan\n1 2 3\n");
  EXPECT_EQ(detectPointFormat(path), PointFormat::Text);
  EXPECT_EQ(readPointFile(path).count, 1u);
  auto binary = dir.write("points.bin", std::string("\x01\x02\x03\x00zz", 6));
  EXPECT_EQ(detectPointFormat(binary), PointFormat::Unknown);
  try {
    readPointFile(binary);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(e.info().hint.find("LAS 1.0-1.4"), std::string::npos);
    EXPECT_NE(e.info().hint.find("PLY"), std::string::npos);
  }
}

TEST(TextWriter, RoundTripKeepsEveryColumn) {
  test::TempDir dir;
  auto in = dir.write("in.csv",
                      "x,y,z,red,green,blue,nx,ny,nz,intensity,classification,gps_time\n"
                      "512345.678,5401234.567,123.45,10,20,30,0.5,-0.25,1,700,2,1e9\n"
                      "512346.001,5401235.999,-0.05,255,0,128,0,0,-1,0.125,6,0.5\n");
  PointCloud source = readPointFile(in);
  for (const char* name : {"out.xyz", "out.csv", "out.txt"}) {
    auto out = dir / name;
    writePointFile(source, out);
    PointCloud back = readPointFile(out);
    ASSERT_EQ(back.count, 2u);
    EXPECT_EQ(back.quantization, source.quantization) << name;
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(back.positions[i], source.positions[i]);
      EXPECT_EQ(back.colors[i], source.colors[i]);
      EXPECT_EQ(back.normals[i], source.normals[i]);
      EXPECT_EQ(back.intensity[i], source.intensity[i]);
      EXPECT_EQ(back.classification[i], source.classification[i]);
      EXPECT_EQ(back.findScalar("gps_time")->as<double>()[i],
                source.findScalar("gps_time")->as<double>()[i]);
    }
  }
  auto pts = dir / "out.pts";
  EXPECT_FALSE(describeWriteLosses(source, pts).empty());
  writePointFile(source, pts);
  PointCloud back = readPointFile(pts);
  EXPECT_EQ(back.colors[1], (Rgba8{255, 0, 128, 255}));
  EXPECT_EQ(back.intensity[1], 0.125f);
}

}  // namespace
}  // namespace parallax
