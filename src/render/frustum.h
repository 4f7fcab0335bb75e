// A view frustum as six planes, for culling chunk and node boxes in world coordinates.
#pragma once

#include <array>
#include <glm/glm.hpp>

#include "core/bounds.h"

namespace parallax {

class Frustum {
 public:
  // From a world-to-clip matrix whose depth range is [0, w] (glClipControl GL_ZERO_TO_ONE, either
  // depth direction). Planes point inwards.
  explicit Frustum(const glm::dmat4& world_to_clip);

  // False only when the box is certainly outside (conservative: a box near a corner of the
  // frustum may pass though it is outside).
  bool intersects(const Bounds3& box) const;

 private:
  std::array<glm::dvec4, 6> planes_;
};

}  // namespace parallax
