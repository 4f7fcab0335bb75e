#include "core/quantization.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace parallax {

Quantization chooseQuantization(const Bounds3& bounds, double margin) {
  Quantization q;
  if (bounds.empty()) return q;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = bounds.min[axis], hi = bounds.max[axis];
    if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
    // Halved before subtracting: near the largest doubles, hi - lo itself overflows.
    double center = 0.5 * lo + 0.5 * hi;
    double half =
        std::min((0.5 * hi - 0.5 * lo) * std::max(margin, 1.0), std::numeric_limits<double>::max());
    // Never finer than a float64's resolution at the centre (below that the offset itself is
    // not exact) and never so fine that a flat axis gets a degenerate scale.
    double magnitude = std::max({std::abs(lo), std::abs(hi), 1e-30});
    half = std::max({half, magnitude * 0x1p-40, 1e-9});
    // 2^30 steps for the half extent: one bit of headroom below int32's 2^31 for rounding and
    // for consumers that add node-local offsets.
    int exponent = int(std::ceil(std::log2(half))) - 30;
    double scale = std::ldexp(1.0, exponent);
    q.scale[axis] = scale;
    q.offset[axis] = std::nearbyint(center / scale) * scale;
  }
  return q;
}

}  // namespace parallax
