// Morton (Z-order) codes: the bits of three 21-bit cell coordinates interleaved into one 63-bit
// key, so sorting by key visits space octant by octant. Used to order points for the renderer
// (neighbours in a draw call are neighbours on screen) and for the octree builder (a node's points
// are one run of the sorted keys).
#pragma once

#include <cstdint>

namespace parallax {

// The low 21 bits of v, spread so that two zero bits follow each (bit i moves to bit 3i).
inline std::uint64_t spreadBits21(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace parallax
