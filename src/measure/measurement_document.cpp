#include "measure/measurement_document.h"

#include <cmath>
#include <fstream>
#include <glm/gtc/quaternion.hpp>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"

namespace parallax {

namespace {

constexpr std::string_view kFormat = "parallax-measurements";
constexpr int kVersion = 1;

nlohmann::json pointJson(const glm::dvec3& p) {
  return nlohmann::json::array({p.x, p.y, p.z});
}

// Reads one document, every error an InputError naming the file and the JSON path.
class DocumentParser {
 public:
  explicit DocumentParser(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& expected,
                         const std::string& found) const {
    throw InputError({.file = file_, .element = path, .expected = expected, .found = found});
  }

  // What a value is, for "found ...": its type and a short quote of it.
  static std::string describe(const nlohmann::json& value) {
    const std::string text = value.dump();
    return std::string(value.type_name()) + " " + quoteInput(text, 60);
  }

  void onlyKeys(const nlohmann::json& object, const std::string& path,
                std::initializer_list<std::string_view> keys) const {
    for (const auto& [key, value] : object.items()) {
      bool known = false;
      for (std::string_view k : keys) known = known || k == key;
      if (!known) {
        std::string list;
        for (std::string_view k : keys) list += (list.empty() ? "'" : ", '") + std::string(k) + "'";
        fail(path, "only the keys " + list, "the key " + quoteInput(key));
      }
    }
  }

  double number(const nlohmann::json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "a number", describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "a finite number", describe(value));
    return x;
  }

  std::string text(const nlohmann::json& value, const std::string& path) const {
    if (!value.is_string()) fail(path, "a string", describe(value));
    return value.get<std::string>();
  }

  glm::dvec3 point(const nlohmann::json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != 3) {
      fail(path, "a point [x, y, z]: an array of 3 numbers", describe(value));
    }
    return {number(value[0], path + "[0]"), number(value[1], path + "[1]"),
            number(value[2], path + "[2]")};
  }

  Camera camera(const nlohmann::json& value, const std::string& path) const {
    Camera camera;
    try {
      camera = cameraFromJson(value);
    } catch (const std::exception& e) {
      fail(path, "a camera as `parallax view` saves it", e.what());
    }
    // cameraFromJson normalises the orientation; a quaternion whose length overflows comes out
    // of that as zeros, which is no rotation at all.
    auto finite3 = [](const glm::dvec3& v) {
      return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const glm::dquat& q = camera.orientation;
    const bool finite = std::abs(glm::length(q) - 1.0) < 1e-6 && std::isfinite(camera.fov_y_deg) &&
                        std::isfinite(camera.ortho_height) && finite3(camera.position) &&
                        finite3(camera.pivot) && finite3(camera.world_up);
    if (!finite) {
      fail(path, "a camera of finite numbers with a non-zero orientation quaternion",
           quoteInput(value.dump(), 80));
    }
    return camera;
  }

  Measurement measurement(const nlohmann::json& value, const std::string& path) const {
    if (!value.is_object()) fail(path, "a measurement object", describe(value));
    onlyKeys(value, path, {"kind", "name", "points", "width"});
    Measurement m;
    if (!value.contains("kind")) fail(path, "a \"kind\"", "none");
    const std::string kind = text(value["kind"], path + ".kind");
    const auto parsed = measurementKindFromName(kind);
    if (!parsed) {
      fail(path + ".kind", "point, distance, height, area, angle or profile", quoteInput(kind));
    }
    m.kind = *parsed;
    if (value.contains("name")) m.name = text(value["name"], path + ".name");
    if (!value.contains("points")) fail(path, "\"points\": [[x, y, z], ...]", "none");
    const nlohmann::json& points = value["points"];
    if (!points.is_array()) fail(path + ".points", "an array of points", describe(points));
    for (std::size_t i = 0; i < points.size(); ++i) {
      m.points.push_back(point(points[i], path + ".points[" + std::to_string(i) + "]"));
    }
    const std::size_t needed = minimumVertices(m.kind);
    const bool exact = hasFixedVertexCount(m.kind);
    if (exact ? m.points.size() != needed : m.points.size() < needed) {
      fail(path + ".points",
           std::string(exact ? "exactly " : "at least ") + std::to_string(needed) +
               (needed == 1 ? " point" : " points") + " for a " + kind,
           std::to_string(m.points.size()));
    }
    if (m.kind == MeasurementKind::Profile) {
      if (!value.contains("width")) fail(path, "a profile's corridor \"width\"", "none");
      m.profile_width = number(value["width"], path + ".width");
      if (!(m.profile_width > 0)) {
        fail(path + ".width", "a width above 0", std::to_string(m.profile_width));
      }
    } else if (value.contains("width")) {
      fail(path + ".width", "no width: only a profile has one", describe(value["width"]));
    }
    return m;
  }

  Annotation annotation(const nlohmann::json& value, const std::string& path) const {
    if (!value.is_object()) fail(path, "an annotation object", describe(value));
    onlyKeys(value, path, {"label", "position", "camera"});
    Annotation a;
    if (!value.contains("label")) fail(path, "a \"label\"", "none");
    a.label = text(value["label"], path + ".label");
    if (!value.contains("position")) fail(path, "a \"position\": [x, y, z]", "none");
    a.position = point(value["position"], path + ".position");
    if (value.contains("camera")) a.camera = camera(value["camera"], path + ".camera");
    return a;
  }

  MeasurementDocument document(const nlohmann::json& json) const {
    if (!json.is_object()) fail("the top level", "a JSON object", describe(json));
    onlyKeys(json, "the top level", {"format", "version", "camera", "measurements", "annotations"});
    if (!json.contains("format") || json["format"] != std::string(kFormat)) {
      fail("format", "\"format\": \"parallax-measurements\"",
           json.contains("format") ? describe(json["format"]) : "none");
    }
    if (!json.contains("version") || !json["version"].is_number_integer() ||
        json["version"] != kVersion) {
      fail("version", "version 1 (this Parallax reads no other)",
           json.contains("version") ? describe(json["version"]) : "none");
    }
    MeasurementDocument document;
    if (json.contains("camera")) document.camera = camera(json["camera"], "camera");
    if (json.contains("measurements")) {
      const nlohmann::json& list = json["measurements"];
      if (!list.is_array()) fail("measurements", "an array", describe(list));
      for (std::size_t i = 0; i < list.size(); ++i) {
        document.measurements.push_back(
            measurement(list[i], "measurements[" + std::to_string(i) + "]"));
      }
    }
    if (json.contains("annotations")) {
      const nlohmann::json& list = json["annotations"];
      if (!list.is_array()) fail("annotations", "an array", describe(list));
      for (std::size_t i = 0; i < list.size(); ++i) {
        document.annotations.push_back(
            annotation(list[i], "annotations[" + std::to_string(i) + "]"));
      }
    }
    return document;
  }

 private:
  std::string file_;
};

}  // namespace

nlohmann::json measurementDocumentToJson(const MeasurementDocument& document) {
  nlohmann::json json = {{"format", kFormat}, {"version", kVersion}};
  if (document.camera) json["camera"] = cameraToJson(*document.camera);
  nlohmann::json measurements = nlohmann::json::array();
  for (const Measurement& m : document.measurements) {
    nlohmann::json item = {{"kind", measurementKindName(m.kind)}};
    if (!m.name.empty()) item["name"] = m.name;
    nlohmann::json points = nlohmann::json::array();
    for (const glm::dvec3& p : m.points) points.push_back(pointJson(p));
    item["points"] = std::move(points);
    if (m.kind == MeasurementKind::Profile) item["width"] = m.profile_width;
    measurements.push_back(std::move(item));
  }
  json["measurements"] = std::move(measurements);
  nlohmann::json annotations = nlohmann::json::array();
  for (const Annotation& a : document.annotations) {
    nlohmann::json item = {{"label", a.label}, {"position", pointJson(a.position)}};
    if (a.camera) item["camera"] = cameraToJson(*a.camera);
    annotations.push_back(std::move(item));
  }
  json["annotations"] = std::move(annotations);
  return json;
}

MeasurementDocument parseMeasurementDocument(std::string_view text, const std::string& file) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    // The byte offset of the error, turned into a line for people.
    const std::size_t offset = std::min<std::size_t>(e.byte, text.size());
    std::uint64_t line = 1;
    for (std::size_t i = 0; i + 1 < offset; ++i) line += text[i] == '\n';
    throw InputError(
        {.file = file, .line = line, .expected = "a JSON measurement document", .found = e.what()});
  } catch (const nlohmann::json::exception& e) {  // e.g. a number too large for a double
    throw InputError({.file = file, .expected = "a JSON measurement document", .found = e.what()});
  }
  return DocumentParser(file).document(json);
}

MeasurementDocument loadMeasurementDocument(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError({.file = path.string(),
                      .expected = "a measurement file (JSON)",
                      .found = "no readable file"});
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  return parseMeasurementDocument(contents.str(), path.string());
}

void saveMeasurementDocument(const MeasurementDocument& document,
                             const std::filesystem::path& path) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out << measurementDocumentToJson(document).dump(2) << "\n";
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw std::runtime_error("cannot write the measurement file " + path.string());
    }
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw std::runtime_error("cannot write the measurement file " + path.string() + ": " +
                             error.message());
  }
}

}  // namespace parallax
