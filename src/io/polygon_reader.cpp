#include "io/polygon_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"

namespace parallax {
namespace {

constexpr const char* kTextExpected = "a vertex 'x y' or 'x,y' (two numbers, an optional third)";

[[noreturn]] void fail(const std::string& name, std::optional<std::uint64_t> line,
                       const std::string& element, const std::string& expected,
                       const std::string& found) {
  throw InputError({.file = name,
                    .line = line,
                    .element = element,
                    .expected = expected,
                    .found = found,
                    .hint = "a GeoJSON Polygon or lines of 'x y' (see --clip-polygon in --help)"});
}

// Drops a closing vertex and checks that a polygon remains.
Polygon2 finished(Polygon2 ring, const std::string& name, const std::string& element) {
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  if (ring.size() < 3) {
    fail(name, std::nullopt, element, "at least 3 distinct vertices", std::to_string(ring.size()));
  }
  return ring;
}

bool isSeparator(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r';
}

Polygon2 parseText(std::string_view text, const std::string& name) {
  Polygon2 ring;
  std::uint64_t line_number = 0;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    std::size_t i = 0;
    while (i < line.size() && isSeparator(line[i])) ++i;
    if (i == line.size() || line[i] == '#') continue;
    double values[3] = {0, 0, 0};
    int count = 0;
    while (i < line.size()) {
      if (count == 3) fail(name, line_number, "vertex", kTextExpected, quoteInput(line));
      const char* first = line.data() + i;
      if (*first == '+') ++first;  // from_chars takes no plus sign
      const auto [stop, error] = std::from_chars(first, line.data() + line.size(), values[count]);
      if (error != std::errc{} || !std::isfinite(values[count]) ||
          (stop != line.data() + line.size() && !isSeparator(*stop))) {
        fail(name, line_number, "vertex", kTextExpected, quoteInput(line));
      }
      ++count;
      i = std::size_t(stop - line.data());
      while (i < line.size() && isSeparator(line[i])) ++i;
    }
    if (count < 2) fail(name, line_number, "vertex", kTextExpected, quoteInput(line));
    ring.push_back({values[0], values[1]});
  }
  return finished(std::move(ring), name, "vertices");
}

using Json = nlohmann::json;

std::string kindOf(const Json& j) {
  return j.is_object()   ? "an object"
         : j.is_array()  ? "an array"
         : j.is_string() ? "a string"
         : j.is_number() ? "a number"
         : j.is_null()   ? "null"
                         : "a value";
}

// A JSON value for a message; invalid UTF-8 in a string is replaced, not thrown on.
std::string shown(const Json& j) {
  return quoteInput(j.dump(-1, ' ', false, Json::error_handler_t::replace));
}

std::string typeOf(const Json& j) {
  const auto t = j.find("type");
  return t != j.end() && t->is_string() ? t->get<std::string>() : std::string();
}

Polygon2 polygonOf(const Json& geometry, const std::string& path, const std::string& name) {
  if (!geometry.is_object() || typeOf(geometry) != "Polygon") {
    fail(name, std::nullopt, path, "a GeoJSON Polygon geometry",
         geometry.is_object() ? "type " + quoteInput(typeOf(geometry)) : kindOf(geometry));
  }
  const auto rings = geometry.find("coordinates");
  if (rings == geometry.end() || !rings->is_array() || rings->empty()) {
    fail(name, std::nullopt, path + ".coordinates", "an array of one ring",
         rings == geometry.end() ? "nothing" : kindOf(*rings));
  }
  if (rings->size() > 1) {
    fail(name, std::nullopt, path + ".coordinates", "one ring (a polygon without holes)",
         std::to_string(rings->size()) + " rings");
  }
  const Json& ring = (*rings)[0];
  const std::string ring_path = path + ".coordinates[0]";
  if (!ring.is_array()) fail(name, std::nullopt, ring_path, "an array of positions", kindOf(ring));
  Polygon2 vertices;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Json& p = ring[i];
    const std::string at = ring_path + "[" + std::to_string(i) + "]";
    if (!p.is_array() || p.size() < 2 || p.size() > 3 || !p[0].is_number() || !p[1].is_number()) {
      fail(name, std::nullopt, at, "a position [x, y] or [x, y, z] of numbers", shown(p));
    }
    const double x = p[0].get<double>(), y = p[1].get<double>();
    if (!std::isfinite(x) || !std::isfinite(y)) {
      fail(name, std::nullopt, at, "finite coordinates", shown(p));
    }
    vertices.push_back({x, y});
  }
  return finished(std::move(vertices), name, ring_path);
}

Polygon2 parseGeoJson(std::string_view text, const std::string& name) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::exception& error) {
    // parse_error, and out_of_range for a number past a double's range.
    fail(name, std::nullopt, "GeoJSON", "valid JSON", quoteInput(error.what(), 240));
  }
  if (!root.is_object()) fail(name, std::nullopt, "$", "a GeoJSON object", kindOf(root));
  const std::string type = typeOf(root);
  if (type == "Polygon") return polygonOf(root, "$", name);
  if (type == "Feature") {
    const auto geometry = root.find("geometry");
    if (geometry == root.end()) fail(name, std::nullopt, "$.geometry", "a Polygon", "nothing");
    return polygonOf(*geometry, "$.geometry", name);
  }
  if (type == "FeatureCollection") {
    const auto features = root.find("features");
    if (features == root.end() || !features->is_array() || features->size() != 1) {
      fail(name, std::nullopt, "$.features", "an array of exactly one Feature",
           features == root.end()  ? "nothing"
           : !features->is_array() ? kindOf(*features)
                                   : std::to_string(features->size()) + " features");
    }
    const Json& feature = (*features)[0];
    if (!feature.is_object() || typeOf(feature) != "Feature" || !feature.contains("geometry")) {
      fail(name, std::nullopt, "$.features[0]", "a Feature with a geometry", shown(feature));
    }
    return polygonOf(feature["geometry"], "$.features[0].geometry", name);
  }
  fail(name, std::nullopt, "$.type", "'Polygon', 'Feature' or 'FeatureCollection'",
       type.empty() ? "no type" : quoteInput(type));
}

}  // namespace

Polygon2 parsePolygon(std::string_view text, const std::string& name) {
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text[first] == '{') return parseGeoJson(text, name);
  return parseText(text, name);
}

Polygon2 readPolygonFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError({.file = path.string(),
                      .expected = "a readable polygon file (GeoJSON or 'x y' lines)",
                      .found = "no such file or no permission"});
  }
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parsePolygon(bytes.str(), path.string());
}

}  // namespace parallax
