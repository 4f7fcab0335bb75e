// Which points are kept: by ASPRS classification and by a region (world half-spaces, kept inside
// their intersection or outside it). One description for every consumer: the rasterizers test it
// per point in their shaders (render/rasterizer.h, keepPoint() in render/point_pass_glsl.cpp),
// the converter on the CPU as points stream in (lod/convert_stages.h), so that what `render`
// shows and what `convert` writes agree. The default keeps every point.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"

namespace parallax {

struct PointFilter {
  // Bit c of word c / 32: keep points of classification c (0-255). All set by default. A point
  // without a classification attribute counts as class 0 ("never classified").
  std::array<std::uint32_t, 8> classes{~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};
  // Half-spaces in world coordinates, (a, b, c, d): a point p is inside where a p.x + b p.y +
  // c p.z + d >= 0 for every plane (a clip box is six). At most kMaxClipPlanes.
  static constexpr std::size_t kMaxClipPlanes = 6;
  std::vector<std::array<double, 4>> clip_planes;
  // Keep the points outside the planes' intersection instead (hide a box's content): a union
  // of half-spaces, which AND-ed planes alone cannot say. Ignored without planes.
  bool clip_outside = false;

  bool keepsAll() const;
  bool keepsEveryClass() const;
  bool keepsClass(int c) const { return (classes[std::size_t(c) / 32] >> (c % 32)) & 1u; }
  void setClass(int c, bool keep);
  // Keeps only the classes in `list` (0-255).
  void keepOnlyClasses(const std::vector<int>& list);
  // Six planes that keep the closed box [min, max] (or its outside); replaces clip_planes.
  void setClipBox(const Bounds3& box, bool outside);
  // The box of clip_planes when they are six that setClipBox wrote (an editor shows it back).
  std::optional<Bounds3> clipBox() const;
  // The region test alone, in double (what the shaders approximate in chunk-relative floats).
  bool keepsPosition(double x, double y, double z) const;

  friend bool operator==(const PointFilter&, const PointFilter&) = default;
};

// The points of `cloud` the filter keeps, every column carried, in their order; `bounds`
// recomputed. A cloud without classification is tested as class 0.
PointCloud filterPoints(const PointCloud& cloud, const PointFilter& filter);

}  // namespace parallax
