#include "render/class_colors.h"

namespace parallax {

namespace {

// Earthy for ground and vegetation (greens darkening with height), warm for buildings, blue for
// water, pinks and reds for noise; wires and towers in yellows and purples, bright against both.
constexpr std::array<std::array<float, 3>, kPaletteClasses> kPalette{{
    {0.50f, 0.50f, 0.50f}, {0.75f, 0.75f, 0.75f}, {0.63f, 0.45f, 0.27f}, {0.55f, 0.85f, 0.45f},
    {0.25f, 0.70f, 0.25f}, {0.05f, 0.45f, 0.10f}, {0.90f, 0.40f, 0.20f}, {1.00f, 0.40f, 0.70f},
    {1.00f, 0.90f, 0.20f}, {0.15f, 0.45f, 0.95f}, {0.60f, 0.35f, 0.25f}, {0.35f, 0.35f, 0.38f},
    {0.95f, 0.95f, 0.60f}, {0.85f, 0.85f, 0.10f}, {0.95f, 0.75f, 0.10f}, {0.55f, 0.25f, 0.75f},
    {0.10f, 0.80f, 0.80f}, {0.70f, 0.70f, 0.95f}, {1.00f, 0.10f, 0.10f},
}};

}  // namespace

std::array<float, 3> classColor(int classification) {
  if (classification < 0 || classification >= int(kPaletteClasses)) return {1.0f, 0.0f, 1.0f};
  return kPalette[std::size_t(classification)];
}

}  // namespace parallax
