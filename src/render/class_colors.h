// The palette of the classification colour mode: ASPRS classes 0-18 (LAS 1.4 R15, table 17),
// anything else magenta so that it stands out. One table: both rasterizers' classColor() is
// generated from it (point_pass_glsl.cpp), and the viewer shows it as the legend of its class
// list.
#pragma once

#include <array>
#include <cstddef>

namespace parallax {

inline constexpr std::size_t kPaletteClasses = 19;  // classes 0-18 have colours of their own

// Linear 0..1 RGB of `classification` as the classification colour mode draws it.
std::array<float, 3> classColor(int classification);

}  // namespace parallax
