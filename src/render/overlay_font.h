// The font of overlay labels: Dear ImGui's built-in one (ProggyClean, 13 pixels, ASCII and
// Latin-1), rasterised by ImGui's font atlas into an 8-bit coverage image. The same font the
// viewer's panel uses, so the labels in a PNG look like those on screen. Needs no GL and no
// ImGui context.
#pragma once

#include <cstdint>
#include <vector>

#include "render/overlay_geometry.h"

namespace parallax {

class OverlayFont final : public OverlayGlyphs {
 public:
  OverlayFont();  // rasterises the atlas (a few milliseconds)

  const OverlayGlyph& glyph(unsigned codepoint) const override;
  float lineHeight() const override { return line_height_; }

  int atlasWidth() const { return width_; }
  int atlasHeight() const { return height_; }
  // atlasWidth() * atlasHeight() coverage bytes, the first row the top (v = 0).
  const std::vector<std::uint8_t>& atlas() const { return atlas_; }

 private:
  static constexpr unsigned kFirst = 0x20, kLast = 0xFF;
  std::vector<OverlayGlyph> glyphs_;  // kFirst .. kLast
  OverlayGlyph fallback_;
  float line_height_ = 13.0f;
  int width_ = 0, height_ = 0;
  std::vector<std::uint8_t> atlas_;
};

}  // namespace parallax
