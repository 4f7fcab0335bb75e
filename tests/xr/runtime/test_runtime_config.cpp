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

Pose parsePose(const nlohmann::json& json, const std::string& where) {
  if (!json.is_object()) throw std::runtime_error(where + " must be an object");
  Pose p;
  numbers(json, "position", p.position, where);
  numbers(json, "orientation", p.orientation, where);
  return p;
}

const char* const kProfiles[] = {"/interaction_profiles/khr/simple_controller",
                                 "/interaction_profiles/oculus/touch_controller",
                                 "/interaction_profiles/valve/index_controller"};

ControllerScript controllerScript(const nlohmann::json& json, const std::string& file) {
  const std::string where = file + ": controllers";
  if (!json.is_object()) throw std::runtime_error(where + " must be an object");
  ControllerScript script;
  if (!json.contains("profile") || !json["profile"].is_string()) {
    throw std::runtime_error(where + ": 'profile' must be an interaction profile's path");
  }
  script.profile = json["profile"].get<std::string>();
  bool known = false;
  for (const char* p : kProfiles) known |= script.profile == p;
  if (!known) throw std::runtime_error(where + ": unknown profile '" + script.profile + "'");
  if (!json.contains("frames") || !json["frames"].is_array()) {
    throw std::runtime_error(where + ": 'frames' must be an array");
  }
  const char* const hand_names[2] = {"left", "right"};
  for (std::size_t i = 0; i < json["frames"].size(); ++i) {
    const auto& entry = json["frames"][i];
    const std::string at = where + ".frames[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("frame") || !entry["frame"].is_number_unsigned()) {
      throw std::runtime_error(at + ": 'frame' must be a frame number from 0");
    }
    ControllerFrame frame;
    frame.frame = entry["frame"].get<std::uint32_t>();
    if (!script.frames.empty() && frame.frame <= script.frames.back().frame) {
      throw std::runtime_error(at + ": frames must increase");
    }
    for (int h = 0; h < 2; ++h) {
      if (!entry.contains(hand_names[h])) continue;
      const auto& hand = entry[hand_names[h]];
      const std::string hand_at = at + "." + hand_names[h];
      if (!hand.is_object() || !hand.contains("grip")) {
        throw std::runtime_error(hand_at + " must be an object with a 'grip' pose");
      }
      HandFrame& out = frame.hands[h];
      out.tracked = true;
      out.grip = parsePose(hand["grip"], hand_at + ".grip");
      out.aim = hand.contains("aim") ? parsePose(hand["aim"], hand_at + ".aim") : out.grip;
      if (!hand.contains("inputs")) continue;
      if (!hand["inputs"].is_object()) throw std::runtime_error(hand_at + ".inputs: an object");
      for (const auto& [name, value] : hand["inputs"].items()) {
        std::array<float, 2> v{0, 0};
        if (value.is_boolean()) {
          v[0] = value.get<bool>() ? 1.0f : 0.0f;
        } else if (value.is_number()) {
          v[0] = value.get<float>();
        } else if (value.is_array() && value.size() == 2 && value[0].is_number() &&
                   value[1].is_number()) {
          v = {value[0].get<float>(), value[1].get<float>()};
        } else {
          throw std::runtime_error(hand_at + ".inputs." + name +
                                   ": expected a number, true, false or [x, y]");
        }
        out.inputs[name] = v;
      }
    }
    script.frames.push_back(std::move(frame));
  }
  return script;
}

}  // namespace

const ControllerFrame* ControllerScript::at(std::uint64_t frame) const {
  const ControllerFrame* found = nullptr;
  for (const ControllerFrame& f : frames) {
    if (f.frame <= frame) found = &f;
  }
  return found;
}

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
  if (json.contains("controllers"))
    config.controllers = controllerScript(json["controllers"], file);
  return config;
}

}  // namespace parallax::xr_test
