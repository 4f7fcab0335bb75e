// A camera path: keyframes at times, interpolated smoothly (Catmull-Rom positions and pivots,
// squad orientations) to render a frame sequence.
//
// JSON: {"keyframes": [{"time": 0, "camera": {...}}, ...]}; "time" is optional (keyframes are
// then one second apart) and must increase. Each "camera" is what saveCamera writes.
#pragma once

#include <filesystem>
#include <vector>

#include "render/camera.h"

namespace parallax {

struct CameraKeyframe {
  double time = 0.0;  // seconds
  Camera camera;
};

class CameraPath {
 public:
  CameraPath() = default;
  // Keyframes sorted by strictly increasing time; at least one.
  explicit CameraPath(std::vector<CameraKeyframe> keyframes);

  double duration() const { return keys_.back().time - keys_.front().time; }
  const std::vector<CameraKeyframe>& keyframes() const { return keys_; }

  // The camera at `time` (clamped to the path's span); passes through every keyframe.
  Camera at(double time) const;
  // The camera of frame `frame` of `frames` spread evenly from the first keyframe to the last
  // (both included).
  Camera frame(int frame, int frames) const;

 private:
  std::vector<CameraKeyframe> keys_;
};

nlohmann::json cameraPathToJson(const CameraPath& path);
// Throws InputError naming the file and the keyframe that is malformed.
CameraPath loadCameraPath(const std::filesystem::path& path);

}  // namespace parallax
