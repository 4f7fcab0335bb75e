// Axis-aligned bounds in world (file) coordinates, as doubles.
#pragma once

#include <algorithm>
#include <array>
#include <limits>

namespace parallax {

struct Bounds3 {
  // An empty box: min above max, so that the first extend() sets both.
  std::array<double, 3> min{std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity()};
  std::array<double, 3> max{-std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity()};

  bool empty() const { return min[0] > max[0]; }

  void extend(double x, double y, double z) {
    min[0] = std::min(min[0], x), max[0] = std::max(max[0], x);
    min[1] = std::min(min[1], y), max[1] = std::max(max[1], y);
    min[2] = std::min(min[2], z), max[2] = std::max(max[2], z);
  }

  void extend(const Bounds3& other) {
    if (other.empty()) return;
    extend(other.min[0], other.min[1], other.min[2]);
    extend(other.max[0], other.max[1], other.max[2]);
  }

  std::array<double, 3> center() const {
    return {(min[0] + max[0]) * 0.5, (min[1] + max[1]) * 0.5, (min[2] + max[2]) * 0.5};
  }
  std::array<double, 3> size() const { return {max[0] - min[0], max[1] - min[1], max[2] - min[2]}; }

  friend bool operator==(const Bounds3&, const Bounds3&) = default;
};

}  // namespace parallax
