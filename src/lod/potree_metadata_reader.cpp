#include "lod/potree_metadata_reader.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/error.h"

namespace parallax {
namespace {

using Json = nlohmann::json;

constexpr std::array<std::pair<std::string_view, PotreeType>, 10> kTypeNames = {{
    {"int8", PotreeType::Int8},
    {"uint8", PotreeType::UInt8},
    {"int16", PotreeType::Int16},
    {"uint16", PotreeType::UInt16},
    {"int32", PotreeType::Int32},
    {"uint32", PotreeType::UInt32},
    {"int64", PotreeType::Int64},
    {"uint64", PotreeType::UInt64},
    {"float", PotreeType::Float},
    {"double", PotreeType::Double},
}};

// Errors name metadata.json and the field as "element" (the JSON path) so a user finds it.
[[noreturn]] void fail(const std::string& file, const std::string& field, std::string expected,
                       std::string found, std::string hint = {}) {
  throw InputError({.file = file,
                    .element = field,
                    .expected = std::move(expected),
                    .found = std::move(found),
                    .hint = std::move(hint)});
}

std::string describe(const Json& value) {
  if (value.is_null()) return "null";
  return quoteInput(value.dump(), 60);
}

const Json& field(const Json& object, const char* key, const std::string& path,
                  const std::string& file) {
  auto it = object.find(key);
  if (it == object.end()) fail(file, path + key, "the field", "none");
  return *it;
}

double number(const Json& object, const char* key, const std::string& path,
              const std::string& file) {
  const Json& value = field(object, key, path, file);
  if (!value.is_number()) fail(file, path + key, "a number", describe(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) fail(file, path + key, "a finite number", describe(value));
  return v;
}

// A non-negative integer that fits `max`.
std::uint64_t count(const Json& object, const char* key, const std::string& path,
                    const std::string& file, std::uint64_t max) {
  const Json& value = field(object, key, path, file);
  if (value.is_number_unsigned() && value.get<std::uint64_t>() <= max) {
    return value.get<std::uint64_t>();
  }
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0 &&
      std::uint64_t(value.get<std::int64_t>()) <= max) {
    return std::uint64_t(value.get<std::int64_t>());
  }
  fail(file, path + key, "an integer from 0 to " + std::to_string(max), describe(value));
}

std::string text(const Json& object, const char* key, const std::string& path,
                 const std::string& file, bool required) {
  auto it = object.find(key);
  if (it == object.end()) {
    if (required) fail(file, path + key, "the field", "none");
    return {};
  }
  if (!it->is_string()) fail(file, path + key, "a string", describe(*it));
  return it->get<std::string>();
}

std::array<double, 3> triple(const Json& object, const char* key, const std::string& path,
                             const std::string& file) {
  const Json& value = field(object, key, path, file);
  if (!value.is_array() || value.size() != 3) {
    fail(file, path + key, "an array of 3 numbers", describe(value));
  }
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number() || !std::isfinite(value[i].get<double>())) {
      fail(file, path + key, "an array of 3 finite numbers", describe(value));
    }
    out[i] = value[i].get<double>();
  }
  return out;
}

// Optional per-element min/max: absent, null or [] gives an empty vector; otherwise numElements
// numbers (a scalar is accepted for one element, as some writers give it).
std::vector<double> range(const Json& attribute, const char* key, int num_elements,
                          const std::string& path, const std::string& file) {
  auto it = attribute.find(key);
  if (it == attribute.end() || it->is_null() || (it->is_array() && it->empty())) return {};
  std::vector<double> out;
  if (it->is_number() && num_elements == 1) {
    out.push_back(it->get<double>());
    return out;
  }
  if (!it->is_array() || it->size() != std::size_t(num_elements)) {
    fail(file, path + key, "an array of " + std::to_string(num_elements) + " numbers",
         describe(*it));
  }
  for (const Json& v : *it) {
    if (!v.is_number()) fail(file, path + key, "numbers", describe(*it));
    out.push_back(v.get<double>());
  }
  return out;
}

PotreeMetadataAttribute parseAttribute(const Json& json, std::size_t index,
                                       const std::string& file) {
  const std::string path = "attributes[" + std::to_string(index) + "].";
  if (!json.is_object()) fail(file, path.substr(0, path.size() - 1), "an object", describe(json));
  PotreeMetadataAttribute a;
  a.name = text(json, "name", path, file, true);
  a.description = text(json, "description", path, file, false);
  const std::string type = text(json, "type", path, file, true);
  std::optional<PotreeType> parsed;
  for (const auto& [name, value] : kTypeNames) {
    if (name == type) parsed = value;
  }
  if (!parsed) {
    fail(file, path + "type",
         "one of int8 uint8 int16 uint16 int32 uint32 int64 uint64 float double", quoteInput(type));
  }
  a.type = *parsed;
  // Bounded so that size arithmetic cannot overflow; no real attribute has more than a few.
  a.num_elements = int(count(json, "numElements", path, file, 1024));
  if (a.num_elements == 0) fail(file, path + "numElements", "at least 1", "0");
  a.size = std::size_t(count(json, "size", path, file, 1 << 16));
  const std::size_t element_size = potreeTypeSize(a.type);
  if (json.contains("elementSize") &&
      count(json, "elementSize", path, file, 1 << 16) != element_size) {
    fail(file, path + "elementSize", std::to_string(element_size) + " for type " + type,
         describe(json["elementSize"]));
  }
  if (a.size != element_size * std::size_t(a.num_elements)) {
    fail(file, path + "size",
         std::to_string(element_size * a.num_elements) + " (numElements " +
             std::to_string(a.num_elements) + " x " + std::to_string(element_size) + " bytes of " +
             type + ")",
         std::to_string(a.size));
  }
  a.min = range(json, "min", a.num_elements, path, file);
  a.max = range(json, "max", a.num_elements, path, file);
  return a;
}

}  // namespace

std::string_view potreeTypeName(PotreeType type) {
  for (const auto& [name, value] : kTypeNames) {
    if (value == type) return name;
  }
  return "?";
}

std::size_t potreeTypeSize(PotreeType type) {
  switch (type) {
    case PotreeType::Int8:
    case PotreeType::UInt8:
      return 1;
    case PotreeType::Int16:
    case PotreeType::UInt16:
      return 2;
    case PotreeType::Int32:
    case PotreeType::UInt32:
    case PotreeType::Float:
      return 4;
    case PotreeType::Int64:
    case PotreeType::UInt64:
    case PotreeType::Double:
      return 8;
  }
  return 1;
}

PotreeMetadata parsePotreeMetadata(std::string_view json_text, const std::string& file) {
  Json json;
  try {
    json = Json::parse(json_text);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based: the byte after the last one read.
    throw InputError({.file = file,
                      .byte_offset = e.byte > 0 ? e.byte - 1 : 0,
                      .expected = "JSON",
                      .found = quoteInput(e.what(), 120),
                      .hint = "metadata.json of a Potree 2.0 directory is a JSON object"});
  } catch (const Json::exception& e) {
    // Also a parse failure: a number too large for any type (out_of_range 406).
    throw InputError({.file = file, .expected = "JSON", .found = quoteInput(e.what(), 120)});
  }
  if (!json.is_object()) fail(file, "(top level)", "a JSON object", describe(json));

  PotreeMetadata m;
  m.version = text(json, "version", "", file, true);
  if (m.version != "2.0") {
    fail(file, "version", "\"2.0\"", quoteInput(m.version),
         "Parallax reads Potree 2.0 (PotreeConverter 2); convert older clouds again with "
         "PotreeConverter 2 or with `parallax convert`");
  }
  m.name = text(json, "name", "", file, false);
  m.description = text(json, "description", "", file, false);
  m.projection = text(json, "projection", "", file, false);
  m.points = count(json, "points", "", file, std::numeric_limits<std::uint64_t>::max());

  m.encoding = text(json, "encoding", "", file, false);
  if (m.encoding.empty()) m.encoding = "DEFAULT";
  if (m.encoding != "DEFAULT") {
    fail(file, "encoding", "\"DEFAULT\"", quoteInput(m.encoding),
         m.encoding == "BROTLI"
             ? "Parallax does not decode BROTLI; convert again with PotreeConverter "
               "--encoding DEFAULT (or with `parallax convert`)"
             : "");
  }

  const Json& box = field(json, "boundingBox", "", file);
  if (!box.is_object()) fail(file, "boundingBox", "an object", describe(box));
  m.cube.min = triple(box, "min", "boundingBox.", file);
  m.cube.max = triple(box, "max", "boundingBox.", file);
  for (int axis = 0; axis < 3; ++axis) {
    if (!(m.cube.min[axis] < m.cube.max[axis])) {
      fail(file, "boundingBox", "min below max on every axis",
           "min " + std::to_string(m.cube.min[axis]) + ", max " + std::to_string(m.cube.max[axis]) +
               " on axis " + "xyz"[axis]);
    }
  }
  m.quantization.scale = triple(json, "scale", "", file);
  m.quantization.offset = triple(json, "offset", "", file);
  for (int axis = 0; axis < 3; ++axis) {
    if (!(m.quantization.scale[axis] > 0)) {
      fail(file, "scale", "positive numbers", std::to_string(m.quantization.scale[axis]));
    }
  }
  m.spacing = number(json, "spacing", "", file);
  if (!(m.spacing > 0)) fail(file, "spacing", "a positive number", std::to_string(m.spacing));

  const Json& hierarchy = field(json, "hierarchy", "", file);
  if (!hierarchy.is_object()) fail(file, "hierarchy", "an object", describe(hierarchy));
  m.hierarchy.first_chunk_size = count(hierarchy, "firstChunkSize", "hierarchy.", file,
                                       std::numeric_limits<std::uint64_t>::max());
  m.hierarchy.step_size = int(count(hierarchy, "stepSize", "hierarchy.", file, 64));
  m.hierarchy.depth = int(count(hierarchy, "depth", "hierarchy.", file, 64));

  const Json& attributes = field(json, "attributes", "", file);
  if (!attributes.is_array() || attributes.empty()) {
    fail(file, "attributes", "a non-empty array", describe(attributes));
  }
  for (std::size_t i = 0; i < attributes.size(); ++i) {
    PotreeMetadataAttribute a = parseAttribute(attributes[i], i, file);
    a.record_offset = m.record_size;
    m.record_size += a.size;
    m.attributes.push_back(std::move(a));
  }
  // Bounds every size computed from it (points < 2^32, so a node's bytes stay below 2^48).
  constexpr std::size_t kMaxRecordSize = 1 << 16;
  if (m.record_size > kMaxRecordSize) {
    fail(file, "attributes", "records of at most " + std::to_string(kMaxRecordSize) + " bytes",
         std::to_string(m.record_size) + " bytes");
  }
  bool has_position = false;
  for (const auto& a : m.attributes) {
    if (a.name != "position") continue;
    if (a.type != PotreeType::Int32 || a.num_elements != 3) {
      fail(file, "attributes.position", "int32 x 3",
           std::string(potreeTypeName(a.type)) + " x " + std::to_string(a.num_elements),
           "the DEFAULT encoding stores positions as int32 with scale and offset");
    }
    has_position = true;
  }
  if (!has_position) fail(file, "attributes", "an attribute named \"position\"", "none");
  return m;
}

}  // namespace parallax
