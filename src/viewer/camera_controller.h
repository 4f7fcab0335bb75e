// Mouse and keyboard to camera: the viewer's input mapping, apart from any window library so
// that it reads as a table of gestures.
//
//   left drag            orbit around the pivot (turntable or free)
//   right/middle drag    pan (shift + left drag too)
//   wheel                dolly towards the point under the cursor
//   double-click         new pivot at the point under the cursor (picked by the caller)
//   fly mode (Tab)       left drag looks around; W A S D move, Q E down and up, shift 4x faster
#pragma once

#include "render/camera.h"

namespace parallax {

struct InputState {
  double cursor_x = 0, cursor_y = 0;  // pixels, origin top-left (window coordinates)
  bool left = false, right = false, middle = false, shift = false;
  bool forward = false, back = false, left_key = false, right_key = false;
  bool down = false, up = false;
};

class CameraController {
 public:
  OrbitMode orbit_mode = OrbitMode::Turntable;
  bool fly = false;
  double fly_speed = 1.0;  // world units per second; the viewer sets it from the cloud's size

  // Applies one frame of input; returns true when the camera changed. `dt` in seconds.
  bool update(Camera& camera, const InputState& input, int width, int height, double dt);
  // Applies wheel steps (positive: towards the scene) at the cursor.
  void scroll(Camera& camera, double steps, double cursor_x, double cursor_y, int width,
              int height);

 private:
  bool dragging_ = false;
  double last_x_ = 0, last_y_ = 0;
};

}  // namespace parallax
