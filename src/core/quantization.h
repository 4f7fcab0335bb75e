// Positions are stored as int32 with a double scale and offset per axis (as LAS and Potree 2.0
// store them): world = quantized * scale + offset. A float carries only 24 bits, which is 6 cm at
// a UTM easting of 500 000 m; an int32 over the extent of a cloud carries 32.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/bounds.h"

namespace parallax {

struct Quantization {
  std::array<double, 3> scale{1.0, 1.0, 1.0};
  std::array<double, 3> offset{0.0, 0.0, 0.0};

  double toWorld(int axis, std::int32_t q) const { return double(q) * scale[axis] + offset[axis]; }

  // Nearest representable value; the caller checks `fits()` first (out-of-range values are
  // clamped, never undefined behaviour).
  std::int32_t toQuantized(int axis, double world) const {
    double q = std::nearbyint((world - offset[axis]) / scale[axis]);
    if (!(q >= double(kMin))) return kMin;  // also catches NaN
    if (q > double(kMax)) return kMax;
    return std::int32_t(q);
  }

  bool fits(int axis, double world) const {
    double q = (world - offset[axis]) / scale[axis];
    return q >= double(kMin) && q <= double(kMax);
  }

  friend bool operator==(const Quantization&, const Quantization&) = default;

  static constexpr std::int32_t kMin = INT32_MIN;
  static constexpr std::int32_t kMax = INT32_MAX;
};

// The finest power-of-two scale, per axis, whose int32 range covers `bounds` grown by `margin`
// times its half extent around its centre; the offset is that centre rounded to a multiple of
// the scale. Why powers of two: a float32 or float64 value is a multiple of its own ulp, so with
// such a scale and offset every value whose ulp is at least the scale is stored exactly. For a
// cloud of half extent h that is every float32 of magnitude above h * margin / 128 (all of a
// UTM-placed cloud) and every double on a binary grid of 2^-30 * h * margin (596732.4375 in a 1 km
// tile); decimal sources (ascii, LAS exports at 0.001) keep well under half their last digit.
// The margin lets a quantization chosen from a sample of points hold points the sample missed;
// readers verify and fall back. Empty or non-finite bounds give the identity quantization.
Quantization chooseQuantization(const Bounds3& bounds, double margin = 1.0);

}  // namespace parallax
