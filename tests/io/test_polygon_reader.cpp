// --clip-polygon files: GeoJSON (Polygon, Feature, FeatureCollection of one) and "x y" text, and
// every malformed case with the file, line or JSON path named.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "io/polygon_reader.h"

namespace parallax::test {
namespace {

const Polygon2 kTriangle{{500100.5, 5000200.25}, {500180.0, 5000200.0}, {500150.0, 5000260.75}};

// The message of the InputError that parsing `text` throws, or "" when it does not throw.
std::string errorOf(const std::string& text, const std::string& name = "area.geojson") {
  try {
    parsePolygon(text, name);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(PolygonReader, GeoJsonPolygonFeatureAndCollection) {
  const std::string ring =
      R"([[[500100.5,5000200.25],[500180,5000200],[500150,5000260.75],[500100.5,5000200.25]]])";
  const std::string polygon = R"({"type":"Polygon","coordinates":)" + ring + "}";
  EXPECT_EQ(parsePolygon(polygon, "a.geojson"), kTriangle);
  EXPECT_EQ(
      parsePolygon(R"({"type":"Feature","properties":{"name":"block"},"geometry":)" + polygon + "}",
                   "a.geojson"),
      kTriangle);
  EXPECT_EQ(parsePolygon(R"(  {"type":"FeatureCollection","features":[{"type":"Feature",)"
                         R"("geometry":)" +
                             polygon + "}]}",
                         "a.geojson"),
            kTriangle);
  // z is ignored; an open ring is accepted too.
  EXPECT_EQ(parsePolygon(R"({"type":"Polygon","coordinates":[[[0,0,5],[4,0,5],[4,3,6]]]})", "b"),
            (Polygon2{{0, 0}, {4, 0}, {4, 3}}));
}

TEST(PolygonReader, TextLinesWithBlanksCommasCommentsAndCrlf) {
  EXPECT_EQ(parsePolygon("# block 12\r\n500100.5 5000200.25\r\n\r\n500180,5000200\r\n"
                         "  500150\t5000260.75  \r\n500100.5;5000200.25\r\n",
                         "block.txt"),
            kTriangle);
  EXPECT_EQ(parsePolygon("0 0 1\n+4 0 1\n4 3 1", "c.txt"), (Polygon2{{0, 0}, {4, 0}, {4, 3}}));
}

TEST(PolygonReader, MalformedTextNamesTheLine) {
  const std::string bad_number = errorOf("0 0\n4 0\n4 x\n", "area.txt");
  EXPECT_NE(bad_number.find("area.txt"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find("line 3"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find("expected a vertex 'x y'"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find("4 x"), std::string::npos) << bad_number;
  EXPECT_NE(errorOf("0 0\n1\n2 2\n", "t.txt").find("line 2"), std::string::npos);
  EXPECT_NE(errorOf("0 0 0 0\n1 1\n2 2\n", "t.txt").find("line 1"), std::string::npos);
  EXPECT_NE(errorOf("0 0\n1 1\n0 0\n", "t.txt").find("at least 3 distinct vertices"),
            std::string::npos);
  EXPECT_NE(errorOf("", "t.txt").find("at least 3 distinct vertices"), std::string::npos);
  EXPECT_NE(errorOf("0 0\n1 nan\n2 2\n", "t.txt").find("line 2"), std::string::npos);
}

TEST(PolygonReader, MalformedGeoJsonNamesThePath) {
  const auto expectError = [](const std::string& text, const std::string& part) {
    const std::string message = errorOf(text);
    EXPECT_NE(message.find("area.geojson"), std::string::npos) << message;
    EXPECT_NE(message.find(part), std::string::npos) << text << "\n" << message;
  };
  expectError(R"({"type":"Polygon","coordinates":[[[0,0],[1,0]],)", "expected valid JSON");
  expectError(R"({"type":"Point","coordinates":[0,0]})", "$.type");
  expectError(R"({"type":"Polygon"})", "$.coordinates");
  expectError(R"({"type":"Polygon","coordinates":[[[0,0],[4,0],[4,4]],[[1,1],[2,1],[2,2]]]})",
              "one ring (a polygon without holes), found 2 rings");
  expectError(R"({"type":"Polygon","coordinates":[[[0,0],[4,"a"],[4,4]]]})",
              "'$.coordinates[0][1]': expected a position [x, y]");
  expectError(R"({"type":"FeatureCollection","features":[]})",
              "'$.features': expected an array of exactly one Feature, found 0 features");
  expectError(R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":)"
              R"({"type":"MultiPolygon","coordinates":[]}}]})",
              "'$.features[0].geometry': expected a GeoJSON Polygon geometry, found type "
              "'MultiPolygon'");
  expectError(R"({"type":"Feature","geometry":null})", "$.geometry");
  // Found by the fuzzer: a number past a double's range, invalid UTF-8 in a string.
  expectError(R"({"type":"Polygon","coordinates":[[[0,0],[1e400,0],[4,4]]]})",
              "expected valid JSON");
  const std::string bad_utf8 =
      errorOf("{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[4,\"\xff\xfe\"],[4,4]]]}");
  EXPECT_NE(bad_utf8.find("expected valid JSON"), std::string::npos) << bad_utf8;
  EXPECT_EQ(bad_utf8.find('\xff'), std::string::npos) << "raw bytes in the message";
}

TEST(PolygonReader, AMissingFileIsAnInputError) {
  EXPECT_THROW(readPolygonFile("/nonexistent/area.geojson"), InputError);
}

}  // namespace
}  // namespace parallax::test
