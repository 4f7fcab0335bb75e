// Little-endian loads and stores of fixed-size values at any (unaligned) byte address: the one
// place the file formats' byte order meets the host's. Every format Parallax reads and writes in
// binary (LAS, LAZ, COPC, Potree, PLY little endian, PCD, E57) stores its numbers little endian,
// and so do the hosts it builds for (x86-64, aarch64), so a copy is the whole conversion; the
// static_assert makes a big-endian build fail here rather than read every file wrong.
#pragma once

#include <bit>
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace parallax {

static_assert(std::endian::native == std::endian::little,
              "Parallax's readers and writers assume a little-endian host");

// The value of type T stored little endian at p (memcpy: p need not be aligned).
template <class T>
inline T loadLE(const std::byte* p) {
  static_assert(std::is_trivially_copyable_v<T>);
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// Writes value little endian at p (memcpy: p need not be aligned).
template <class T>
inline void storeLE(std::byte* p, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::memcpy(p, &value, sizeof(T));
}

}  // namespace parallax
