// What the test runtime reports and does, read from the JSON file named by PARALLAX_XR_TEST:
//   {"views": [{"fov": {"left": L, "right": R, "up": U, "down": D},
//               "pose": {"position": [x, y, z], "orientation": [x, y, z, w]}}, ...],
//    "width": W, "height": H, "frames": N, "output": "DIR",
//    "controllers": {"profile": "/interaction_profiles/oculus/touch_controller",
//                    "frames": [{"frame": F,
//                                "left": {"grip": POSE, "aim": POSE,
//                                         "inputs": {"squeeze/value": 1, "thumbstick": [x, y]}},
//                                "right": {...}}, ...]}}
// Angles in radians as XrFovf holds them (left and down usually negative), poses (POSE:
// {"position": [x, y, z], "orientation": [x, y, z, w]}) in stage space (metres, y up). Every field
// but "views" may be left out; see the defaults below.
//
// Controllers: "profile" is the interaction profile the runtime reports for both hands (one of
// khr/simple_controller, oculus/touch_controller, valve/index_controller). Each entry of
// "frames" holds from its frame F (counted from 0, as the PNGs are) until the next entry's: a
// hand named in it is tracked, at its grip pose and aim pose ("aim" defaults to "grip"), with the
// inputs listed, by their path under /user/hand/<hand>/input/ ("trigger/value", "a/click",
// "thumbstick", ...: a number, true or false, or [x, y] for a stick) and every other input at 0;
// a hand left out is not tracked and its actions are inactive. Entries in increasing frame order.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace parallax::xr_test {

struct ViewConfig {
  float fov_left = -0.8f, fov_right = 0.8f, fov_up = 0.8f, fov_down = -0.8f;
  float position[3] = {0, 1.6f, 0};
  float orientation[4] = {0, 0, 0, 1};  // x, y, z, w (XrQuaternionf's order)
};

struct Pose {
  float position[3] = {0, 0, 0};
  float orientation[4] = {0, 0, 0, 1};  // x, y, z, w
};

struct HandFrame {
  bool tracked = false;
  Pose grip, aim;
  std::map<std::string, std::array<float, 2>> inputs;  // a stick's x, y; a button or value in [0]
};

struct ControllerFrame {
  std::uint32_t frame = 0;
  HandFrame hands[2];  // left, right
};

struct ControllerScript {
  std::string profile;  // empty: no controllers
  std::vector<ControllerFrame> frames;
  // The entry that holds at `frame`; nullptr before the first.
  const ControllerFrame* at(std::uint64_t frame) const;
};

struct RuntimeConfig {
  std::vector<ViewConfig> views;  // exactly 2 (a stereo headset)
  std::uint32_t width = 64, height = 64;
  std::uint32_t frames = 3;  // frames ended before the runtime asks the session to stop
  std::string output;        // empty: nothing written
  ControllerScript controllers;
};

// Without PARALLAX_XR_TEST: two eyes 64 mm apart at 1.6 m, 0.8 rad each side, 64 x 64, 3 frames,
// nothing written (enough for hello_xr). Throws std::runtime_error naming the file and the field
// that is missing or malformed.
RuntimeConfig loadRuntimeConfig();

}  // namespace parallax::xr_test
