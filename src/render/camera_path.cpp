#include "render/camera_path.h"

#include <algorithm>
#include <cassert>
#include <fstream>
#include <glm/gtx/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/error.h"

namespace parallax {

namespace {

// Centripetal would be safer for uneven spacing; uniform Catmull-Rom is enough for hand-placed
// keyframes and keeps the curve through every key.
glm::dvec3 catmullRom(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                      const glm::dvec3& p3, double t) {
  const double t2 = t * t, t3 = t2 * t;
  return 0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3);
}

// q and -q are the same rotation; interpolate along the shorter arc.
glm::dquat sameHemisphere(const glm::dquat& reference, glm::dquat q) {
  return glm::dot(reference, q) < 0 ? -q : q;
}

}  // namespace

CameraPath::CameraPath(std::vector<CameraKeyframe> keyframes) : keys_(std::move(keyframes)) {
  assert(!keys_.empty() && "a camera path needs at least one keyframe");
  for (std::size_t i = 1; i < keys_.size(); ++i) {
    assert(keys_[i].time > keys_[i - 1].time && "keyframe times must increase");
    keys_[i].camera.orientation =
        sameHemisphere(keys_[i - 1].camera.orientation, keys_[i].camera.orientation);
  }
}

Camera CameraPath::at(double time) const {
  if (keys_.size() == 1 || time <= keys_.front().time) return keys_.front().camera;
  if (time >= keys_.back().time) return keys_.back().camera;
  const auto next = std::upper_bound(keys_.begin(), keys_.end(), time,
                                     [](double t, const CameraKeyframe& k) { return t < k.time; });
  const std::size_t i = std::size_t(next - keys_.begin()) - 1;
  const std::size_t last = keys_.size() - 1;
  const Camera& c0 = keys_[i == 0 ? 0 : i - 1].camera;
  const Camera& c1 = keys_[i].camera;
  const Camera& c2 = keys_[i + 1].camera;
  const Camera& c3 = keys_[std::min(i + 2, last)].camera;
  const double t = (time - keys_[i].time) / (keys_[i + 1].time - keys_[i].time);

  Camera camera = c1;
  camera.position = catmullRom(c0.position, c1.position, c2.position, c3.position, t);
  camera.pivot = catmullRom(c0.pivot, c1.pivot, c2.pivot, c3.pivot, t);
  // Squad (Shoemake 1987): a smooth (C1) spline through the key orientations.
  const glm::dquat a = glm::intermediate(c0.orientation, c1.orientation, c2.orientation);
  const glm::dquat b = glm::intermediate(c1.orientation, c2.orientation, c3.orientation);
  camera.orientation = glm::normalize(glm::squad(c1.orientation, c2.orientation, a, b, t));
  camera.fov_y_deg = glm::mix(c1.fov_y_deg, c2.fov_y_deg, t);
  camera.ortho_height = glm::mix(c1.ortho_height, c2.ortho_height, t);
  return camera;
}

Camera CameraPath::frame(int frame, int frames) const {
  if (frames <= 1) return keys_.front().camera;
  return at(keys_.front().time + duration() * double(frame) / double(frames - 1));
}

nlohmann::json cameraPathToJson(const CameraPath& path) {
  nlohmann::json keyframes = nlohmann::json::array();
  for (const CameraKeyframe& key : path.keyframes()) {
    keyframes.push_back({{"time", key.time}, {"camera", cameraToJson(key.camera)}});
  }
  return {{"keyframes", keyframes}};
}

CameraPath loadCameraPath(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(
        {.file = path.string(), .expected = "a camera path JSON file", .found = "no file"});
  }
  std::vector<CameraKeyframe> keys;
  std::size_t index = 0;
  try {
    const nlohmann::json json = nlohmann::json::parse(in);
    const nlohmann::json& list = json.at("keyframes");
    for (; index < list.size(); ++index) {
      const nlohmann::json& item = list.at(index);
      CameraKeyframe key;
      key.time = item.contains("time") ? item.at("time").get<double>() : double(index);
      key.camera = cameraFromJson(item.at("camera"));
      if (!keys.empty() && key.time <= keys.back().time) {
        throw std::runtime_error("its time " + std::to_string(key.time) +
                                 " is not after the previous keyframe's");
      }
      keys.push_back(key);
    }
  } catch (const std::exception& e) {
    throw InputError({.file = path.string(),
                      .element = "keyframe " + std::to_string(index),
                      .expected = R"({"keyframes": [{"time": t, "camera": {...}}, ...]})",
                      .found = e.what()});
  }
  if (keys.empty()) {
    throw InputError({.file = path.string(), .expected = "at least one keyframe", .found = "none"});
  }
  return CameraPath(std::move(keys));
}

}  // namespace parallax
