// Scalar types of point attributes, named as PLY names them (the richest of our formats).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

namespace parallax {

enum class ScalarType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

// Size of one value in bytes: 1, 2, 4 or 8.
std::size_t scalarSize(ScalarType type);

// PLY's canonical name: char uchar short ushort int uint float double.
std::string_view scalarName(ScalarType type);

// Accepts the canonical names and the sized aliases (int8 uint8 int16 uint16 int32 uint32 float32
// float64); nullopt for anything else.
std::optional<ScalarType> parseScalarType(std::string_view name);

constexpr bool isFloatingPoint(ScalarType type) {
  return type == ScalarType::Float32 || type == ScalarType::Float64;
}

// double -> float as IEEE rounding does it, without undefined behaviour: values from FLT_MAX up
// to the midpoint towards 2^128 round to FLT_MAX, values beyond it to infinity.
inline float narrowToFloat(double v) {
  constexpr double kMax = 0x1.fffffep127, kOverflow = 0x1.ffffffp127;
  if (v >= kOverflow) return __builtin_inff();
  if (v <= -kOverflow) return -__builtin_inff();
  if (v > kMax) return float(kMax);
  if (v < -kMax) return -float(kMax);
  return float(v);
}

// double -> integer type T, rounded half away from zero and clamped to T's range (NaN gives its
// minimum). Truncation after adding 0.5 instead of std::round: no libm call in per-value loops.
template <class T>
T roundToInteger(double v) {
  if (!(v >= double(std::numeric_limits<T>::min()))) return std::numeric_limits<T>::min();
  if (v >= double(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
  return T(v + (v >= 0 ? 0.5 : -0.5));
}

}  // namespace parallax
