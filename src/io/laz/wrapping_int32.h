// Two's-complement arithmetic on 32-bit integers that wraps, as LASzip's coders compute (their
// differences and predictions rely on it), written through unsigned arithmetic since signed
// overflow is undefined in C++. Shared by the point-wise and the layered items.
#pragma once

#include <cstdint>

namespace parallax::laz {

inline std::int32_t wrapAdd(std::int32_t a, std::int32_t b) {
  return std::int32_t(std::uint32_t(a) + std::uint32_t(b));
}
inline std::int32_t wrapSub(std::int32_t a, std::int32_t b) {
  return std::int32_t(std::uint32_t(a) - std::uint32_t(b));
}
inline std::int32_t wrapMul(std::int32_t a, std::int32_t b) {
  return std::int32_t(std::uint32_t(a) * std::uint32_t(b));
}

}  // namespace parallax::laz
