#include "core/point_filter.h"

#include <cassert>

#include "core/point_gather.h"

namespace parallax {

bool PointFilter::keepsEveryClass() const {
  for (const std::uint32_t word : classes) {
    if (word != ~0u) return false;
  }
  return true;
}

bool PointFilter::keepsAll() const {
  return keepsEveryClass() && clip_planes.empty();
}

void PointFilter::setClass(int c, bool keep) {
  assert(c >= 0 && c < 256 && "a classification is 0-255");
  const std::uint32_t bit = 1u << (c % 32);
  std::uint32_t& word = classes[std::size_t(c) / 32];
  word = keep ? word | bit : word & ~bit;
}

void PointFilter::keepOnlyClasses(const std::vector<int>& list) {
  classes.fill(0u);
  for (const int c : list) setClass(c, true);
}

void PointFilter::setClipBox(const Bounds3& box, bool outside) {
  clip_planes = {{1, 0, 0, -box.min[0]}, {-1, 0, 0, box.max[0]}, {0, 1, 0, -box.min[1]},
                 {0, -1, 0, box.max[1]}, {0, 0, 1, -box.min[2]}, {0, 0, -1, box.max[2]}};
  clip_outside = outside;
}

std::optional<Bounds3> PointFilter::clipBox() const {
  if (clip_planes.size() != 6) return std::nullopt;
  Bounds3 box;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto& low = clip_planes[2 * axis];
    const auto& high = clip_planes[2 * axis + 1];
    for (std::size_t k = 0; k < 3; ++k) {
      if (low[k] != (k == axis ? 1.0 : 0.0) || high[k] != (k == axis ? -1.0 : 0.0)) {
        return std::nullopt;
      }
    }
    box.min[axis] = -low[3];
    box.max[axis] = high[3];
  }
  return box;
}

bool PointFilter::keepsPosition(double x, double y, double z) const {
  if (clip_planes.empty()) return true;
  bool inside = true;
  for (const auto& p : clip_planes) inside = inside && p[0] * x + p[1] * y + p[2] * z + p[3] >= 0;
  return inside != clip_outside;
}

PointCloud filterPoints(const PointCloud& cloud, const PointFilter& filter) {
  // Indices first, then each column gathered once: the test reads positions and classes only.
  std::vector<std::uint64_t> kept;
  const bool every_class = filter.keepsEveryClass();
  const bool class_zero = filter.keepsClass(0);
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    if (!every_class &&
        !(cloud.hasClassification() ? filter.keepsClass(cloud.classification[i]) : class_zero)) {
      continue;
    }
    if (!filter.keepsPosition(cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i))) continue;
    kept.push_back(i);
  }
  PointCloud out = gatherPoints(cloud, kept);
  out.computeBounds();
  return out;
}

}  // namespace parallax
