#include "render/overlay_font.h"

#include <imgui.h>

#include <stdexcept>

namespace parallax {

namespace {

OverlayGlyph fromImGui(const ImFontGlyph& g) {
  return {g.X0, g.Y0, g.X1, g.Y1, g.U0, g.V0, g.U1, g.V1, g.AdvanceX};
}

}  // namespace

OverlayFont::OverlayFont() {
  // An atlas of our own: ImGui's font atlas works without a context (its allocator is global).
  ImFontAtlas atlas;
  ImFont* font = atlas.AddFontDefault();
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  atlas.GetTexDataAsAlpha8(&pixels, &width, &height);
  if (!font || !pixels || width <= 0 || height <= 0) {
    throw std::runtime_error("cannot rasterise Dear ImGui's default font for overlay labels");
  }
  width_ = width, height_ = height;
  atlas_.assign(pixels, pixels + std::size_t(width) * std::size_t(height));
  line_height_ = font->FontSize;
  const ImFontGlyph* question = font->FindGlyph(ImWchar('?'));
  if (question) fallback_ = fromImGui(*question);
  for (unsigned c = kFirst; c <= kLast; ++c) {
    const ImFontGlyph* g = font->FindGlyphNoFallback(ImWchar(c));
    glyphs_.push_back(g ? fromImGui(*g) : fallback_);
  }
}

const OverlayGlyph& OverlayFont::glyph(unsigned codepoint) const {
  if (codepoint < kFirst || codepoint > kLast) return fallback_;
  return glyphs_[codepoint - kFirst];
}

}  // namespace parallax
