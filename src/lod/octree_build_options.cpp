#include "lod/octree_build_options.h"

#include <algorithm>
#include <cassert>

namespace parallax {

const char* samplingMethodName(SamplingMethod method) {
  return method == SamplingMethod::Poisson ? "poisson" : "random";
}

bool parseSamplingMethod(std::string_view name, SamplingMethod& method) {
  if (name == "poisson") {
    method = SamplingMethod::Poisson;
    return true;
  }
  if (name == "random") {
    method = SamplingMethod::Random;
    return true;
  }
  return false;
}

Bounds3 octreeCube(const Bounds3& bounds) {
  Bounds3 cube;
  if (bounds.empty()) {
    cube.min = {0.0, 0.0, 0.0};
    cube.max = {1.0, 1.0, 1.0};
    return cube;
  }
  const auto size = bounds.size();
  double edge = std::max({size[0], size[1], size[2]});
  if (!(edge > 0.0)) edge = 1.0;
  cube.min = bounds.min;
  for (int axis = 0; axis < 3; ++axis) cube.max[axis] = cube.min[axis] + edge;
  return cube;
}

double rootSpacing(const Bounds3& cube, const OctreeBuildOptions& options) {
  if (options.spacing > 0.0) return options.spacing;
  return (cube.max[0] - cube.min[0]) / 128.0;
}

Bounds3 childBox(const Bounds3& box, int index) {
  Bounds3 child = box;
  const auto center = box.center();
  const int bits[3] = {4, 2, 1};
  for (int axis = 0; axis < 3; ++axis) {
    if (index & bits[axis]) {
      child.min[axis] = center[axis];
    } else {
      child.max[axis] = center[axis];
    }
  }
  return child;
}

Bounds3 nodeBox(const Bounds3& cube, std::string_view name) {
  assert(!name.empty() && name[0] == 'r' && "node names start with 'r'");
  Bounds3 box = cube;
  for (std::size_t i = 1; i < name.size(); ++i) box = childBox(box, name[i] - '0');
  return box;
}

}  // namespace parallax
