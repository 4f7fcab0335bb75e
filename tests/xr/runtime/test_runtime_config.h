// What the test runtime reports and does, read from the JSON file named by PARALLAX_XR_TEST:
//   {"views": [{"fov": {"left": L, "right": R, "up": U, "down": D},
//               "pose": {"position": [x, y, z], "orientation": [x, y, z, w]}}, ...],
//    "width": W, "height": H, "frames": N, "output": "DIR"}
// Angles in radians as XrFovf holds them (left and down usually negative), poses in stage space
// (metres, y up). Every field but "views" may be left out; see the defaults below.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace parallax::xr_test {

struct ViewConfig {
  float fov_left = -0.8f, fov_right = 0.8f, fov_up = 0.8f, fov_down = -0.8f;
  float position[3] = {0, 1.6f, 0};
  float orientation[4] = {0, 0, 0, 1};  // x, y, z, w (XrQuaternionf's order)
};

struct RuntimeConfig {
  std::vector<ViewConfig> views;  // exactly 2 (a stereo headset)
  std::uint32_t width = 64, height = 64;
  std::uint32_t frames = 3;  // frames ended before the runtime asks the session to stop
  std::string output;        // empty: nothing written
};

// Without PARALLAX_XR_TEST: two eyes 64 mm apart at 1.6 m, 0.8 rad each side, 64 x 64, 3 frames,
// nothing written (enough for hello_xr). Throws std::runtime_error naming the file and the field
// that is missing or malformed.
RuntimeConfig loadRuntimeConfig();

}  // namespace parallax::xr_test
