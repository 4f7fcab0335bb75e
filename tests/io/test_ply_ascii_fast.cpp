// The ascii fast path (io/ply_ascii_fast_decoder.h) through the reader: it must give exactly what
// the general line parser gives, line for line, and leave every line it cannot take whole to that
// parser (values and errors alike). Each file here is read twice: once in a layout the fast path
// takes, once with a trailing empty list property, which sends every line to the general parser
// and adds no column; the two clouds must be equal.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/ply_reader.h"
#include "io/ply_test_files.h"

namespace parallax {
namespace {

using test::asBytes;
using test::catchInputError;
using test::CaughtInputError;
using test::expectExpectedAndFound;
using test::expectMessageHas;
using test::plyHeader;
using test::readPlyText;

const std::vector<std::string> kPhotogrammetry = {
    "property float x",   "property float y",     "property float z",
    "property float nx",  "property float ny",    "property float nz",
    "property uchar red", "property uchar green", "property uchar blue"};

// An ascii file of `lines` (each without its line end) in `properties`, lines ended by `eol`;
// with `general_only`, a trailing "property list uchar int unused" and " 0" on every line.
std::string asciiFile(const std::vector<std::string>& properties,
                      const std::vector<std::string>& lines, bool general_only,
                      const std::string& eol = "\n") {
  std::string header = plyHeader(PlyFormat::Ascii, {}, eol);
  std::string declared = "element vertex " + std::to_string(lines.size()) + eol;
  for (const std::string& property : properties) declared += property + eol;
  if (general_only) declared += "property list uchar int unused" + eol;
  header.insert(header.find("end_header"), declared);
  std::string body;
  for (const std::string& line : lines) body += line + (general_only ? " 0" : "") + eol;
  return header + body;
}

// Reads the file both ways (and serially and in parallel), checks they agree, returns one.
PointCloud readBothWays(const std::vector<std::string>& properties,
                        const std::vector<std::string>& lines, const std::string& eol = "\n") {
  const PointCloud fast = readPlyText(asciiFile(properties, lines, false, eol), true);
  const PointCloud general = readPlyText(asciiFile(properties, lines, true, eol), true);
  const PointCloud serial = readPlyText(asciiFile(properties, lines, false, eol), false);
  test::expectSamePoints(fast, general);
  test::expectSamePoints(fast, serial);
  EXPECT_EQ(fast.bounds, general.bounds);
  return readPlyText(asciiFile(properties, lines, false, eol));
}

// Typical lines of a photogrammetry export, to surround the lines under test: the fast path only
// runs where 40 bytes or more follow a value.
std::vector<std::string> withTypicalLines(std::vector<std::string> lines) {
  for (int i = 0; i < 8; ++i) {
    lines.push_back("0.80130386 5.3736343 -1.5534592 0.015092595 -0.03753764 0.9991812 124 137 " +
                    std::to_string(60 + i));
  }
  return lines;
}

std::uint32_t bits(float value) {
  return std::bit_cast<std::uint32_t>(value);
}

TEST(PlyAsciiFast, TypicalLinesAreExact) {
  const std::vector<std::string> lines = withTypicalLines(
      {"9.430561 2.1922455 -1.7125435 0.024939781 -0.050472308 0.99841404 81 108 41",
       "-19.338814 -14.459511 1.912281 0.9669332 0.25502977 0 133 137 134"});
  const PointCloud cloud = readBothWays(kPhotogrammetry, lines);
  ASSERT_EQ(cloud.count, lines.size());
  EXPECT_EQ(bits(cloud.normals[0].x), bits(std::strtof("0.024939781", nullptr)));
  EXPECT_EQ(bits(cloud.normals[0].y), bits(std::strtof("-0.050472308", nullptr)));
  EXPECT_EQ(bits(cloud.normals[1].z), bits(0.0f));
  EXPECT_EQ(cloud.colors[0], (Rgba8{81, 108, 41, 255}));
  EXPECT_EQ(cloud.colors[1], (Rgba8{133, 137, 134, 255}));
  EXPECT_EQ(cloud.colors[9], (Rgba8{124, 137, 67, 255}));
}

TEST(PlyAsciiFast, NumbersOfEveryShapeMatchTheGeneralParser) {
  // Each line has an odd number in the normals (stored as floats, unquantized): long mantissas,
  // leading zeros, exponents, signs, denormals, overflow, float midpoints.
  // (NaN is left out: the clouds are compared with ==.)
  const std::vector<std::string> odd = {"-0",
                                        "-0.000",
                                        ".5",
                                        "5.",
                                        "-.25",
                                        "+1.5",
                                        "1e-3",
                                        "2.5E+2",
                                        "1e400",
                                        "-1e400",
                                        "1e-40",
                                        "1.4e-45",
                                        "0.1234567890123456789",
                                        "00000000000000000001.5",
                                        "16777217",
                                        "16777219",
                                        "16777217.00001",
                                        "0.30000001192092896",
                                        "123456789012345678901234567890",
                                        "3.4028235e38",
                                        "inf",
                                        "-inf"};
  for (const std::string& value : odd) {
    SCOPED_TRACE(value);
    const PointCloud cloud = readBothWays(
        kPhotogrammetry, withTypicalLines({"1.5 2.5 3.5 " + value + " 0.5 " + value + " 1 2 3"}));
    const float expected = std::strtof(value.c_str(), nullptr);
    if (std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(cloud.normals[0].x));
    } else {
      EXPECT_EQ(bits(cloud.normals[0].x), bits(expected));
      EXPECT_EQ(bits(cloud.normals[0].z), bits(expected));
    }
  }
}

TEST(PlyAsciiFast, IntegerSpellingsOfColours) {
  // Leading zeros, a '+', "-0", integers written as floats: the general parser's rules.
  const PointCloud cloud = readBothWays(
      kPhotogrammetry, withTypicalLines({"1 2 3 0 0 1 007 +5 -0", "1 2 3 0 0 1 255.000000 2.55e2 0",
                                         "1 2 3 0 0 1 0 00000000255 1"}));
  EXPECT_EQ(cloud.colors[0], (Rgba8{7, 5, 0, 255}));
  EXPECT_EQ(cloud.colors[1], (Rgba8{255, 255, 0, 255}));
  EXPECT_EQ(cloud.colors[2], (Rgba8{0, 255, 1, 255}));
}

TEST(PlyAsciiFast, BlanksCrlfAndTheLastLine) {
  // Tabs, runs of spaces, blanks before the line end, and a last line without one.
  std::vector<std::string> lines =
      withTypicalLines({"  1.25\t2.5   3.75 0 0 1 10 20 30   ", "\t-1 -2 -3 0.5 0.5 0.5 1 2 3\t"});
  const PointCloud lf = readBothWays(kPhotogrammetry, lines);
  const PointCloud crlf = readBothWays(kPhotogrammetry, lines, "\r\n");
  test::expectSamePoints(lf, crlf);
  EXPECT_EQ(lf.colors[0], (Rgba8{10, 20, 30, 255}));
  EXPECT_EQ(lf.normals[1], (Float3{0.5f, 0.5f, 0.5f}));

  std::string no_final_eol = asciiFile(kPhotogrammetry, lines, false);
  no_final_eol.pop_back();
  test::expectSamePoints(readPlyText(no_final_eol), lf);
}

TEST(PlyAsciiFast, DoublePositionsAndExtraColumns) {
  // Positions as double (exact doubles, UTM-sized), colours between them, scalar columns of
  // each kind the fast path stores, and one it does not (the whole file then takes the general
  // path).
  const std::vector<std::string> properties = {
      "property double x",    "property uchar red",       "property double y",
      "property double z",    "property float quality",   "property double gps_time",
      "property uchar flags", "property float intensity", "property uchar classification"};
  const std::vector<std::string> lines = {
      "512000.125 200 4100000.0625 120.5 0.75 271828.18284590452 7 0.25 2",
      "512345.1234567891 0 4100001.987654321 -3.25 1e-3 314159.265 255 1 6",
      "512001 1 4100002 121 -0.5 1.5 0 0.5 9", "512002.5 2 4100003.5 122 0.125 2.5 1 0.75 9",
      "512003.5 3 4100004.5 123 0.125 3.5 2 0.75 9"};
  const PointCloud cloud = readBothWays(properties, lines);
  EXPECT_EQ(cloud.source.position, ScalarType::Float64);
  test::expectScalarValues<double>(cloud, "gps_time", ScalarType::Float64,
                                   {271828.18284590452, 314159.265, 1.5, 2.5, 3.5});
  test::expectScalarValues<float>(cloud, "quality", ScalarType::Float32,
                                  {0.75f, 1e-3f, -0.5f, 0.125f, 0.125f});
  test::expectScalarValues<std::uint8_t>(cloud, "flags", ScalarType::UInt8, {7, 255, 0, 1, 2});
  EXPECT_EQ(cloud.intensity[1], 1.0f);
  EXPECT_EQ(cloud.classification[1], 6);
  EXPECT_EQ(cloud.colors[1].r, 0);

  std::vector<std::string> unsupported = properties;
  unsupported.push_back("property int label");
  std::vector<std::string> labelled = lines;
  for (std::string& line : labelled) line += " -7";
  const PointCloud with_label = readBothWays(unsupported, labelled);
  test::expectScalarValues<std::int32_t>(with_label, "label", ScalarType::Int32,
                                         {-7, -7, -7, -7, -7});
}

TEST(PlyAsciiFast, ARunOfLinesItCannotTakeThenLinesItCan) {
  // 40 lines in exponent notation (the fast path gives up on the range after 8 refusals in a
  // row), then typical lines; and the reverse.
  std::vector<std::string> exponents;
  for (int i = 0; i < 40; ++i) {
    exponents.push_back(std::to_string(i) + "e-1 2.5e0 -3e+2 1e-2 0 1 " + std::to_string(i) +
                        " 2 3");
  }
  const PointCloud first = readBothWays(kPhotogrammetry, withTypicalLines(exponents));
  EXPECT_EQ(bits(first.normals[7].x), bits(0.01f));
  EXPECT_EQ(first.colors[39], (Rgba8{39, 2, 3, 255}));
  std::vector<std::string> reversed = withTypicalLines({});
  reversed.insert(reversed.end(), exponents.begin(), exponents.end());
  const PointCloud second = readBothWays(kPhotogrammetry, reversed);
  EXPECT_EQ(second.colors[8 + 39], (Rgba8{39, 2, 3, 255}));
}

// ---------------------------------------------------------------------------------------------
// Errors: the line the fast path refuses is reported by the general parser, with its line.

CaughtInputError readError(const std::string& bytes, bool parallel) {
  PlyReadOptions options;
  options.parallel = parallel;
  return catchInputError([&] { readPlyFromMemory(asBytes(bytes), "scan.ply", options); });
}

// The header of asciiFile(kPhotogrammetry, ...) has 13 lines: the body starts at line 14.
constexpr int kFirstBodyLine = 14;

TEST(PlyAsciiFast, BadValuesAreReportedWithTheirLineAndProperty) {
  struct Case {
    std::string line;
    std::string property;
    std::string found;
  };
  const std::vector<Case> cases = {
      {"1 2 3 0 0 1 256 0 0", "red", "256"},  {"1 2 3 0 0 1 0 -1 0", "green", "-1"},
      {"1 2 3 0 0 1 0 0 2.5", "blue", "2.5"}, {"1 2 3 0 0 1 0 0 12345678", "blue", "12345678"},
      {"1 2 abc 0 0 1 0 0 0", "z", "abc"},    {"1 2 3.5.1 0 0 1 0 0 0", "z", "3.5.1"},
      {"1 2 3 0 0 1 1 2", "blue", ""},        {"1 2 3 0 0 1 1 2 3 4", "", "4"},
      {"1e400 2 3 0 0 1 1 2 3", "x", "inf"}};
  for (const Case& c : cases) {
    for (bool parallel : {true, false}) {
      SCOPED_TRACE(c.line + (parallel ? " parallel" : " serial"));
      // The bad line third, with typical lines after it, so that the fast path meets it.
      const std::vector<std::string> lines =
          withTypicalLines({"1 2 3 0 0 1 4 5 6", "1 2 3 0 0 1 4 5 6", c.line});
      const CaughtInputError caught = readError(asciiFile(kPhotogrammetry, lines, false), parallel);
      expectMessageHas(
          caught, {"scan.ply", "line " + std::to_string(kFirstBodyLine + 2), "element 'vertex'"});
      if (!c.property.empty()) expectMessageHas(caught, {"property '" + c.property + "'"});
      if (!c.found.empty()) expectMessageHas(caught, {c.found});
      expectExpectedAndFound(caught);
    }
  }
}

TEST(PlyAsciiFast, ManyLinesAcrossRangesMatchTheGeneralParser) {
  // Enough lines for several ranges of the parallel decode, with odd lines sprinkled in.
  std::vector<std::string> lines;
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  for (int i = 0; i < 30000; ++i) {
    char line[160];
    if (i % 997 == 0) {
      std::snprintf(line, sizeof line, "%.17g %.3e %d 0 0 1 %u %u %u", double(next()) / 7e3,
                    double(next()) * 1e-6, int(next() % 1000) - 500, next() % 256, next() % 256,
                    next() % 256);
    } else {
      std::snprintf(line, sizeof line, "%.9g %.8g %.7g %.9g %.9g %.9g %u %u %u",
                    double(next()) / 3e6 - 700.0, double(next()) / 1e7, double(next()) / 1e8,
                    double(int(next() % 2000) - 1000) / 1000.0, double(next()) / 4.3e9,
                    double(next()) / 4.3e9, next() % 256, next() % 256, next() % 256);
    }
    lines.push_back(line);
  }
  const PointCloud cloud = readBothWays(kPhotogrammetry, lines);
  ASSERT_EQ(cloud.count, lines.size());
  for (std::size_t i : {std::size_t(1), std::size_t(997), std::size_t(29999)}) {
    float nx = 0.0f;
    unsigned r = 0, g = 0, b = 0;
    char x[64], y[64], z[64], nxt[64], ny[64], nz[64];
    ASSERT_EQ(std::sscanf(lines[i].c_str(), "%63s %63s %63s %63s %63s %63s %u %u %u", x, y, z, nxt,
                          ny, nz, &r, &g, &b),
              9);
    nx = std::strtof(nxt, nullptr);
    EXPECT_EQ(bits(cloud.normals[i].x), bits(nx)) << lines[i];
    EXPECT_EQ(cloud.colors[i], (Rgba8{std::uint8_t(r), std::uint8_t(g), std::uint8_t(b), 255}));
  }
}

}  // namespace
}  // namespace parallax
