#include "viewer/camera_controller.h"

#include <cmath>

namespace parallax {

namespace {
// Radians of orbit per pixel of drag: a drag across a 1000-pixel window turns about 180 degrees.
constexpr double kOrbitPerPixel = 0.0055;
constexpr double kLookPerPixel = 0.003;
constexpr double kDollyPerStep = 0.85;
}  // namespace

bool CameraController::update(Camera& camera, const InputState& input, int, int height, double dt) {
  bool changed = false;
  const bool any_button = input.left || input.right || input.middle;
  if (any_button && !dragging_) {
    last_x_ = input.cursor_x, last_y_ = input.cursor_y;
  }
  dragging_ = any_button;
  const double dx = input.cursor_x - last_x_, dy = input.cursor_y - last_y_;
  last_x_ = input.cursor_x, last_y_ = input.cursor_y;

  if (any_button && (dx != 0 || dy != 0)) {
    const bool pan = input.right || input.middle || (input.left && input.shift);
    if (pan) {
      camera.pan(dx, dy, height);
    } else if (fly) {
      camera.flyLook(-dx * kLookPerPixel, -dy * kLookPerPixel);
    } else {
      // Dragging right turns the scene right, i.e. the camera to the left around the pivot.
      camera.orbit(-dx * kOrbitPerPixel, dy * kOrbitPerPixel, orbit_mode);
    }
    changed = true;
  }
  if (fly) {
    const double step = fly_speed * dt * (input.shift ? 4.0 : 1.0);
    const glm::dvec3 move((input.right_key ? 1 : 0) - (input.left_key ? 1 : 0),
                          (input.up ? 1 : 0) - (input.down ? 1 : 0),
                          (input.forward ? 1 : 0) - (input.back ? 1 : 0));
    if (move != glm::dvec3(0.0)) {
      camera.flyMove(move * step);
      changed = true;
    }
  }
  return changed;
}

void CameraController::scroll(Camera& camera, double steps, double cursor_x, double cursor_y,
                              int width, int height) {
  if (width <= 0 || height <= 0 || steps == 0) return;
  const glm::dvec2 ndc(2.0 * cursor_x / width - 1.0, 1.0 - 2.0 * cursor_y / height);
  camera.dolly(std::pow(kDollyPerStep, steps), ndc, double(width) / height);
}

}  // namespace parallax
