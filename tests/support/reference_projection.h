// The tests' own perspective projection, written out from what a user gives on the command line
// (--eye, --target, --up, --fov, the picture's size; for stereo the eye separation and the
// convergence distance), so that picking and overlay tests do not check the product's camera
// with the product's camera (render/camera.h).
//
// Conventions, as the command line documents them: the camera looks from `eye` at `target`;
// the picture's up is `up` made perpendicular to the view; the field of view is vertical; x grows
// to the right and window y upwards from the bottom-left corner, a pixel's centre at +0.5. A
// stereo eye sits half the separation to the left or right of `eye`, looks the same way (never
// toe-in), and its frustum is sheared so that the plane at the convergence distance projects
// where the mono camera puts it (the off-axis method).
#pragma once

#include <cmath>
#include <optional>

#include <glm/glm.hpp>

namespace parallax::test {

struct ReferenceView {
  glm::dvec3 eye{0.0}, target{0.0}, up{0.0, 0.0, 1.0};
  double fov_y_deg = 60.0;
  // The view's rectangle in the picture (window coordinates, bottom-left origin).
  int x = 0, y = 0, width = 1, height = 1;
  // Stereo: this eye's offset along the camera's right (negative: the left eye) and the
  // convergence distance; 0 for a mono view.
  double eye_offset = 0.0, convergence = 0.0;
};

struct ReferencePoint {
  glm::dvec2 window{0.0};  // window coordinates of the point's centre
  double depth = 0.0;      // distance in front of the eye along the view direction
  // The picture row and column it falls in (top row 0), as `pick --pixel` and screenshots count.
  int column() const { return int(std::floor(window.x)); }
  int row(int picture_height) const { return picture_height - 1 - int(std::floor(window.y)); }
};

// Where `p` lands in `view`; nothing for a point behind the eye or outside the view's rectangle.
inline std::optional<ReferencePoint> referenceProject(const ReferenceView& view,
                                                      const glm::dvec3& p) {
  const glm::dvec3 forward = glm::normalize(view.target - view.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, view.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const glm::dvec3 eye = view.eye + view.eye_offset * right;
  const glm::dvec3 d = p - eye;
  const double depth = glm::dot(d, forward);
  if (!(depth > 0)) return std::nullopt;
  // Similar triangles: at `depth` the view is 2 depth tan(fov / 2) high and `aspect` times as
  // wide. The off-axis shear moves x by the eye's offset scaled to the convergence plane, so a
  // point there straight ahead of the mono camera lands in the middle of each eye's view.
  const double tan_half = std::tan(view.fov_y_deg * M_PI / 360.0);
  const double aspect = double(view.width) / double(view.height);
  double x = glm::dot(d, right);
  if (view.convergence > 0) x += view.eye_offset * depth / view.convergence;
  const double ndc_x = x / (depth * tan_half * aspect);
  const double ndc_y = glm::dot(d, up) / (depth * tan_half);
  if (std::abs(ndc_x) > 1 || std::abs(ndc_y) > 1) return std::nullopt;
  ReferencePoint out;
  out.window = {view.x + (ndc_x + 1) / 2 * view.width, view.y + (ndc_y + 1) / 2 * view.height};
  out.depth = depth;
  return out;
}

}  // namespace parallax::test
