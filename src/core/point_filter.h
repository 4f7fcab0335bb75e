// Which points are kept: by ASPRS classification, by return (return number of number of
// returns), by ranges of intensity, elevation and GPS time, and by a region (world half-spaces
// and a polygon extruded along z, kept inside their intersection or outside it). One description
// for every consumer: the rasterizers test it per point in their shaders (render/rasterizer.h,
// keepPoint() in render/point_pass_glsl.cpp), the converter on the CPU as points stream in
// (lod/convert_stages.h), so that what `render` shows and what `convert` writes agree. The
// default keeps every point.
//
// Points that lack an attribute a test reads count as: class 0 ("never classified"), return 1
// of 1 (a single return: what a file without returns, e.g. photogrammetry, is), intensity 0 and
// GPS time 0. Return numbers and numbers of returns above 15 count as 15 (LAS 1.4 stores 4 bits;
// the GPU buffers hold 4 bits each).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/bounds.h"
#include "core/column_names.h"
#include "core/point_cloud.h"

namespace parallax {

// The scalar columns the return and GPS time tests read (the names io/las_reader.h gives LAS
// fields, and the Potree and COPC readers give theirs).
namespace filter_names = column_names;

// The kinds of return a user names (`--returns first,last`): a point is kept when it is any of
// the kinds listed. For return r of n: first r = 1, last r = n, intermediate 1 < r < n,
// single n = 1, multiple n > 1.
enum class ReturnKind { First, Last, Intermediate, Single, Multiple };
bool isReturnKind(ReturnKind kind, int return_number, int number_of_returns);

// An inclusive range of an attribute: min <= v <= max.
struct ValueRange {
  double min = 0.0, max = 0.0;
  bool contains(double v) const { return v >= min && v <= max; }
  friend bool operator==(const ValueRange&, const ValueRange&) = default;
};

// A clip box: [min, max] in its own frame, turned by yaw_degrees about the vertical line through
// its centre (counter-clockwise seen from above).
struct ClipBox {
  Bounds3 box;
  double yaw_degrees = 0.0;

  // The footprint's corners (x, y), counter-clockwise in the box's own frame from (min, min),
  // turned about the centre.
  std::array<std::array<double, 2>, 4> corners() const;

  friend bool operator==(const ClipBox&, const ClipBox&) = default;
};

struct PointFilter {
  // Bit c of word c / 32: keep points of classification c (0-255). All set by default.
  std::array<std::uint32_t, 8> classes{~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};
  // Bit k = n * 16 + r of word k / 32: keep return r of n (each 0-15). All set by default. A
  // 256-bit table like the classes', so that the shaders test both the same way and any mix of
  // kinds and explicit numbers is one lookup.
  std::array<std::uint32_t, 8> returns{~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};
  // Attribute ranges; absent: no bound. Elevation is world z.
  std::optional<ValueRange> intensity, elevation, gps_time;
  // Half-spaces in world coordinates, (a, b, c, d): a point p is inside where a p.x + b p.y +
  // c p.z + d >= 0 for every plane (a clip box is six). At most kMaxClipPlanes.
  static constexpr std::size_t kMaxClipPlanes = 6;
  std::vector<std::array<double, 4>> clip_planes;
  // A polygon (x, y in world coordinates; the last vertex joins the first; at least 3 when not
  // empty) extruded along z: a point is inside where (x, y) is, by the even-odd rule. With clip
  // planes, the region is the intersection of both (a box bounds the polygon in z). The shaders
  // take at most kMaxGpuPolygonVertices; the CPU has no limit.
  static constexpr std::size_t kMaxGpuPolygonVertices = 256;
  std::vector<std::array<double, 2>> polygon;
  // Keep the points outside the region instead (hide a box's content): a union of half-spaces,
  // which AND-ed planes alone cannot say. Ignored without a region.
  bool clip_outside = false;
  // Keep the region's points and the others alike, and tint the region's (render and view: a
  // drawing mode, which the converter refuses). Ignored without a region; clip_outside unused.
  bool clip_highlight = false;

  bool keepsAll() const;
  bool keepsEveryClass() const;
  bool keepsEveryReturn() const;
  bool hasRegion() const { return !clip_planes.empty() || !polygon.empty(); }
  bool keepsClass(int c) const { return (classes[std::size_t(c) / 32] >> (c % 32)) & 1u; }
  void setClass(int c, bool keep);
  // Keeps only the classes in `list` (0-255).
  void keepOnlyClasses(const std::vector<int>& list);
  // Return r of n, each clamped to 0-15 as the GPU stores them.
  bool keepsReturn(int r, int n) const;
  void setReturn(int r, int n, bool keep);
  // Keeps only the returns that are one of `kinds` or whose return number is in `numbers`.
  void keepOnlyReturns(const std::vector<ReturnKind>& kinds, const std::vector<int>& numbers);
  // Six planes that keep the closed box [min, max] (or its outside), turned by `yaw_degrees`
  // about the vertical line through its centre (counter-clockwise seen from above: a box
  // aligned with a street or a wall); replaces clip_planes. Unturned, the planes hold min and max
  // exactly.
  void setClipBox(const Bounds3& box, bool outside, double yaw_degrees = 0.0);
  // The box of clip_planes when they are six that setClipBox wrote (an editor shows it back);
  // a turned box comes back to within rounding.
  std::optional<ClipBox> clipBox() const;
  // The position tests (elevation, and the region inside or outside unless highlighted), in
  // double: what the shaders approximate in chunk-relative floats.
  bool keepsPosition(double x, double y, double z) const;
  // Whether a point is in the region (planes and polygon; false without a region).
  bool inRegion(double x, double y, double z) const;
  // False when no point inside `box` (world coordinates, closed) can be kept by the position
  // tests (elevation, region): an octree node whose cube this says false of need not be read.
  // Conservative: true whenever a point might be kept (a box across a turned plane, a polygon's
  // bounding rectangle met, an outside region).
  bool mayKeepIn(const Bounds3& box) const;
  // Whether (x, y) is inside `polygon` (even-odd rule; false for an empty polygon).
  bool insidePolygon(double x, double y) const;

  friend bool operator==(const PointFilter&, const PointFilter&) = default;
};

// The points of `cloud` the filter keeps, every column carried, in their order; `bounds`
// recomputed. Missing attributes count as the header says (class 0, return 1 of 1, ...).
PointCloud filterPoints(const PointCloud& cloud, const PointFilter& filter);

}  // namespace parallax
