// The one rule between a colour channel's 16 bits (LAS, E57, PCD and PLY ushort channels, the
// stored_colors of a PointCloud) and its 8 bits for display (PointCloud::colors). Every reader,
// writer and binding goes through these, so that a colour read, shown, edited and written again
// keeps its bits, whichever of them touched it.
#pragma once

#include <cstdint>

namespace parallax {

// 8 -> 16 bits: c * 257 (0xab -> 0xabab), which maps 255 onto 65535 exactly, as LAS 1.4 R15 asks
// (the full range), and which colorTo8Bits turns back into c.
constexpr std::uint16_t colorTo16Bits(std::uint8_t c) {
  return std::uint16_t(c * 257u);
}

// 16 -> 8 bits: the nearest of v / 257, so 65535 -> 255 and c * 257 -> c.
constexpr std::uint8_t colorTo8Bits(std::uint16_t v) {
  return std::uint8_t((unsigned(v) + 128u) / 257u);
}

// A display channel of a file whose 16-bit channels may hold 8-bit values unscaled: many LAS
// writers store 0..255 in them, and a reader that finds every value of a file below 256 shows
// them as they are (`unscaled`); otherwise the nearest of v / 257.
constexpr std::uint8_t shownColor(std::uint16_t v, bool unscaled) {
  return unscaled ? std::uint8_t(v) : colorTo8Bits(v);
}

// The 16 bits a changed display channel is stored as under the same rule: the value itself in an
// unscaled file, c * 257 otherwise.
constexpr std::uint16_t storedColor(std::uint8_t c, bool unscaled) {
  return unscaled ? std::uint16_t(c) : colorTo16Bits(c);
}

static_assert(colorTo8Bits(colorTo16Bits(0)) == 0 && colorTo8Bits(colorTo16Bits(128)) == 128 &&
              colorTo8Bits(colorTo16Bits(255)) == 255 && colorTo8Bits(65535) == 255);

}  // namespace parallax
