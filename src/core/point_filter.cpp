#include "core/point_filter.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "core/point_gather.h"

namespace parallax {
namespace {

int clampNibble(int v) {
  return std::clamp(v, 0, 15);
}

bool allSet(const std::array<std::uint32_t, 8>& words) {
  return std::all_of(words.begin(), words.end(), [](std::uint32_t w) { return w == ~0u; });
}

// A scalar column's value as a 4-bit return field: rounded, clamped to 0-15.
int nibbleOf(const ScalarColumn* column, std::size_t i, int absent) {
  if (!column) return absent;
  const double v = column->valueAsDouble(i);
  return std::isnan(v) ? 0 : clampNibble(int(std::clamp(std::lround(v), -1l, 16l)));
}

}  // namespace

bool isReturnKind(ReturnKind kind, int r, int n) {
  switch (kind) {
    case ReturnKind::First:
      return r == 1;
    case ReturnKind::Last:
      return r == n;
    case ReturnKind::Intermediate:
      return r > 1 && r < n;
    case ReturnKind::Single:
      return n == 1;
    case ReturnKind::Multiple:
      return n > 1;
  }
  return false;
}

bool PointFilter::keepsEveryClass() const {
  return allSet(classes);
}

bool PointFilter::keepsEveryReturn() const {
  return allSet(returns);
}

bool PointFilter::keepsAll() const {
  return keepsEveryClass() && keepsEveryReturn() && !intensity && !elevation && !gps_time &&
         !hasRegion();
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

bool PointFilter::keepsReturn(int r, int n) const {
  const int k = clampNibble(n) * 16 + clampNibble(r);
  return (returns[std::size_t(k) / 32] >> (k % 32)) & 1u;
}

void PointFilter::setReturn(int r, int n, bool keep) {
  assert(r >= 0 && r < 16 && n >= 0 && n < 16 && "return fields are 0-15");
  const int k = n * 16 + r;
  const std::uint32_t bit = 1u << (k % 32);
  std::uint32_t& word = returns[std::size_t(k) / 32];
  word = keep ? word | bit : word & ~bit;
}

void PointFilter::keepOnlyReturns(const std::vector<ReturnKind>& kinds,
                                  const std::vector<int>& numbers) {
  for (int n = 0; n < 16; ++n) {
    for (int r = 0; r < 16; ++r) {
      bool keep = std::find(numbers.begin(), numbers.end(), r) != numbers.end();
      for (const ReturnKind kind : kinds) keep = keep || isReturnKind(kind, r, n);
      setReturn(r, n, keep);
    }
  }
}

std::array<std::array<double, 2>, 4> ClipBox::corners() const {
  const double yaw = yaw_degrees * (std::numbers::pi / 180.0);
  const double cs = std::cos(yaw), sn = std::sin(yaw);
  const double cx = 0.5 * (box.min[0] + box.max[0]), cy = 0.5 * (box.min[1] + box.max[1]);
  const double hu = 0.5 * (box.max[0] - box.min[0]), hv = 0.5 * (box.max[1] - box.min[1]);
  std::array<std::array<double, 2>, 4> turned{};
  const std::array<std::array<double, 2>, 4> signs{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  for (std::size_t i = 0; i < 4; ++i) {
    const double u = signs[i][0] * hu, v = signs[i][1] * hv;
    turned[i] = {cx + cs * u - sn * v, cy + sn * u + cs * v};
  }
  return turned;
}

void PointFilter::setClipBox(const Bounds3& box, bool outside, double yaw_degrees) {
  clip_outside = outside;
  if (yaw_degrees == 0.0) {
    clip_planes = {{1, 0, 0, -box.min[0]}, {-1, 0, 0, box.max[0]}, {0, 1, 0, -box.min[1]},
                   {0, -1, 0, box.max[1]}, {0, 0, 1, -box.min[2]}, {0, 0, -1, box.max[2]}};
    return;
  }
  // The box's own axes u (its x) and v (its y) in world coordinates; a point p is inside where
  // |u.(p - c)| <= half width, |v.(p - c)| <= half depth and z is in [min, max]. The offsets are
  // half extents minus or plus u.c, so no plane constant carries a UTM coordinate's rounding
  // beyond that of u.c itself.
  const double yaw = yaw_degrees * (std::numbers::pi / 180.0);
  const double cs = std::cos(yaw), sn = std::sin(yaw);
  const double cx = 0.5 * (box.min[0] + box.max[0]), cy = 0.5 * (box.min[1] + box.max[1]);
  const double hu = 0.5 * (box.max[0] - box.min[0]), hv = 0.5 * (box.max[1] - box.min[1]);
  const double uc = cs * cx + sn * cy, vc = -sn * cx + cs * cy;
  clip_planes = {{cs, sn, 0, hu - uc},  {-cs, -sn, 0, hu + uc}, {-sn, cs, 0, hv - vc},
                 {sn, -cs, 0, hv + vc}, {0, 0, 1, -box.min[2]}, {0, 0, -1, box.max[2]}};
}

std::optional<ClipBox> PointFilter::clipBox() const {
  if (clip_planes.size() != 6) return std::nullopt;
  // z: the vertical planes setClipBox writes for every yaw.
  const auto& bottom = clip_planes[4];
  const auto& top = clip_planes[5];
  if (bottom != std::array<double, 4>{0, 0, 1, bottom[3]} ||
      top != std::array<double, 4>{0, 0, -1, top[3]}) {
    return std::nullopt;
  }
  ClipBox clip;
  clip.box.min[2] = -bottom[3];
  clip.box.max[2] = top[3];
  const auto& low_u = clip_planes[0];
  const auto& high_u = clip_planes[1];
  const auto& low_v = clip_planes[2];
  const auto& high_v = clip_planes[3];
  if (low_u == std::array<double, 4>{1, 0, 0, low_u[3]} &&
      high_u == std::array<double, 4>{-1, 0, 0, high_u[3]} &&
      low_v == std::array<double, 4>{0, 1, 0, low_v[3]} &&
      high_v == std::array<double, 4>{0, -1, 0, high_v[3]}) {
    clip.box.min[0] = -low_u[3], clip.box.max[0] = high_u[3];
    clip.box.min[1] = -low_v[3], clip.box.max[1] = high_v[3];
    return clip;
  }
  // Turned: u = (cos, sin), v = (-sin, cos), each pair of planes opposite.
  const double cs = low_u[0], sn = low_u[1];
  const bool turned = low_u[2] == 0 && std::abs(cs * cs + sn * sn - 1.0) < 1e-12 &&
                      high_u == std::array<double, 4>{-cs, -sn, 0, high_u[3]} &&
                      low_v == std::array<double, 4>{-sn, cs, 0, low_v[3]} &&
                      high_v == std::array<double, 4>{sn, -cs, 0, high_v[3]};
  if (!turned) return std::nullopt;
  const double hu = 0.5 * (low_u[3] + high_u[3]), uc = 0.5 * (high_u[3] - low_u[3]);
  const double hv = 0.5 * (low_v[3] + high_v[3]), vc = 0.5 * (high_v[3] - low_v[3]);
  const double cx = cs * uc - sn * vc, cy = sn * uc + cs * vc;
  clip.box.min[0] = cx - hu, clip.box.max[0] = cx + hu;
  clip.box.min[1] = cy - hv, clip.box.max[1] = cy + hv;
  clip.yaw_degrees = std::atan2(sn, cs) * (180.0 / std::numbers::pi);
  return clip;
}

bool PointFilter::insidePolygon(double x, double y) const {
  // Crossing number: a ray towards +x crosses the boundary an odd number of times from inside.
  // The shaders run the same expression in chunk-relative floats (point_pass_glsl.cpp).
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n ? n - 1 : 0; i < n; j = i++) {
    const auto& a = polygon[i];
    const auto& b = polygon[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) {
      inside = !inside;
    }
  }
  return inside;
}

bool PointFilter::inRegion(double x, double y, double z) const {
  if (!hasRegion()) return false;
  bool inside = true;
  for (const auto& p : clip_planes) inside = inside && p[0] * x + p[1] * y + p[2] * z + p[3] >= 0;
  if (inside && !polygon.empty()) inside = insidePolygon(x, y);
  return inside;
}

bool PointFilter::mayKeepIn(const Bounds3& box) const {
  if (box.empty()) return false;
  if (elevation && (box.max[2] < elevation->min || box.min[2] > elevation->max)) return false;
  if (!hasRegion() || clip_highlight || clip_outside) return true;
  // A plane keeps nothing of the box when even the corner farthest along its normal is behind it.
  for (const auto& p : clip_planes) {
    double best = p[3];
    for (int axis = 0; axis < 3; ++axis) {
      best += p[std::size_t(axis)] *
              (p[std::size_t(axis)] >= 0 ? box.max[std::size_t(axis)] : box.min[std::size_t(axis)]);
    }
    if (best < 0) return false;
  }
  if (!polygon.empty()) {
    double min_x = polygon[0][0], max_x = min_x, min_y = polygon[0][1], max_y = min_y;
    for (const auto& v : polygon) {
      min_x = std::min(min_x, v[0]), max_x = std::max(max_x, v[0]);
      min_y = std::min(min_y, v[1]), max_y = std::max(max_y, v[1]);
    }
    if (box.max[0] < min_x || box.min[0] > max_x || box.max[1] < min_y || box.min[1] > max_y) {
      return false;
    }
  }
  return true;
}

bool PointFilter::keepsPosition(double x, double y, double z) const {
  if (elevation && !elevation->contains(z)) return false;
  if (!hasRegion() || clip_highlight) return true;
  return inRegion(x, y, z) != clip_outside;
}

PointCloud filterPoints(const PointCloud& cloud, const PointFilter& filter) {
  // Indices first, then each column gathered once: the test reads only what the filter needs.
  std::vector<std::uint64_t> kept;
  const bool every_class = filter.keepsEveryClass();
  const bool class_zero = filter.keepsClass(0);
  const bool every_return = filter.keepsEveryReturn();
  const ScalarColumn* return_number = cloud.findScalar(filter_names::kReturnNumber);
  const ScalarColumn* number_of_returns = cloud.findScalar(filter_names::kNumberOfReturns);
  const ScalarColumn* gps_time = cloud.findScalar(filter_names::kGpsTime);
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    if (!every_class &&
        !(cloud.hasClassification() ? filter.keepsClass(cloud.classification[i]) : class_zero)) {
      continue;
    }
    if (!every_return &&
        !filter.keepsReturn(nibbleOf(return_number, i, 1), nibbleOf(number_of_returns, i, 1))) {
      continue;
    }
    if (filter.intensity &&
        !filter.intensity->contains(cloud.hasIntensity() ? double(cloud.intensity[i]) : 0.0)) {
      continue;
    }
    if (filter.gps_time &&
        !filter.gps_time->contains(gps_time ? gps_time->valueAsDouble(i) : 0.0)) {
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
