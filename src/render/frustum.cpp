#include "render/frustum.h"

namespace parallax {

Frustum::Frustum(const glm::dmat4& m) {
  // Gribb and Hartmann, "Fast extraction of viewing frustum planes from the world-view-projection
  // matrix" (2001), with 0 <= z <= w for the depth planes. glm is column-major: row i is m[.][i].
  auto row = [&](int i) { return glm::dvec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
  const glm::dvec4 x = row(0), y = row(1), z = row(2), w = row(3);
  planes_ = {w + x, w - x, w + y, w - y, z, w - z};
}

bool Frustum::intersects(const Bounds3& box) const {
  if (box.empty()) return false;
  for (const glm::dvec4& plane : planes_) {
    // The box corner farthest along the plane's normal.
    const glm::dvec3 p(plane.x >= 0 ? box.max[0] : box.min[0],
                       plane.y >= 0 ? box.max[1] : box.min[1],
                       plane.z >= 0 ? box.max[2] : box.min[2]);
    if (plane.x * p.x + plane.y * p.y + plane.z * p.z + plane.w < 0) return false;
  }
  return true;
}

}  // namespace parallax
