#include "test_runtime_config.h"

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace parallax::xr_test {
namespace {

float number(const nlohmann::json& object, const char* key, const std::string& where) {
  if (!object.contains(key) || !object.at(key).is_number()) {
    throw std::runtime_error(where + ": '" + key + "' must be a number");
  }
  return object.at(key).get<float>();
}

template <std::size_t N>
void numbers(const nlohmann::json& object, const char* key, float (&out)[N],
             const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_array() || it->size() != N) {
    throw std::runtime_error(where + ": '" + key + "' must be an array of " + std::to_string(N) +
                             " numbers");
  }
  for (std::size_t i = 0; i < N; ++i) {
    if (!(*it)[i].is_number()) {
      throw std::runtime_error(where + ": '" + key + "'[" + std::to_string(i) +
                               "] must be a number");
    }
    out[i] = (*it)[i].get<float>();
  }
}

}  // namespace

RuntimeConfig loadRuntimeConfig() {
  RuntimeConfig config;
  const char* path = std::getenv("PARALLAX_XR_TEST");
  if (path == nullptr || *path == '\0') {
    config.views.resize(2);
    config.views[0].position[0] = -0.032f;
    config.views[1].position[0] = 0.032f;
    return config;
  }
  const std::string file = path;
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot be opened (PARALLAX_XR_TEST)");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file + ": not JSON: " + e.what());
  }
  if (!json.is_object() || !json.contains("views") || !json["views"].is_array() ||
      json["views"].size() != 2) {
    throw std::runtime_error(file + ": 'views' must be an array of 2 views (left eye first)");
  }
  for (std::size_t v = 0; v < 2; ++v) {
    const std::string where = file + ": views[" + std::to_string(v) + "]";
    const auto& view = json["views"][v];
    if (!view.is_object() || !view.contains("fov") || !view.contains("pose")) {
      throw std::runtime_error(where + " must be an object with 'fov' and 'pose'");
    }
    ViewConfig c;
    const auto& fov = view["fov"];
    if (!fov.is_object()) throw std::runtime_error(where + ": 'fov' must be an object");
    c.fov_left = number(fov, "left", where + ".fov");
    c.fov_right = number(fov, "right", where + ".fov");
    c.fov_up = number(fov, "up", where + ".fov");
    c.fov_down = number(fov, "down", where + ".fov");
    if (!(c.fov_left < c.fov_right && c.fov_down < c.fov_up)) {
      throw std::runtime_error(where + ".fov: expected left < right and down < up");
    }
    const auto& pose = view["pose"];
    if (!pose.is_object()) throw std::runtime_error(where + ": 'pose' must be an object");
    numbers(pose, "position", c.position, where + ".pose");
    numbers(pose, "orientation", c.orientation, where + ".pose");
    config.views.push_back(c);
  }
  const auto positive = [&](const char* key, std::uint32_t& out) {
    if (!json.contains(key)) return;
    if (!json[key].is_number_integer() || json[key].get<long long>() <= 0 ||
        json[key].get<long long>() > 16384) {
      throw std::runtime_error(file + ": '" + key + "' must be an integer from 1 to 16384");
    }
    out = json[key].get<std::uint32_t>();
  };
  positive("width", config.width);
  positive("height", config.height);
  positive("frames", config.frames);
  if (json.contains("output")) {
    if (!json["output"].is_string()) throw std::runtime_error(file + ": 'output' must be a string");
    config.output = json["output"].get<std::string>();
  }
  return config;
}

}  // namespace parallax::xr_test
