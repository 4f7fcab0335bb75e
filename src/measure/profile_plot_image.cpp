#include "measure/profile_plot_image.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <string>

namespace parallax {

namespace {

// The picture being drawn: pixel writes clipped to it.
class PlotCanvas {
 public:
  PlotCanvas(ProfilePlotImage& image) : image_(image) {}

  void set(int x, int y, const std::array<std::uint8_t, 4>& color) {
    if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
    std::copy(color.begin(), color.end(), at(x, y));
  }
  // `coverage` (0..255) of `color` over what is there (the picture stays opaque).
  void blend(int x, int y, const std::array<std::uint8_t, 4>& color, int coverage) {
    if (coverage <= 0 || x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
    std::uint8_t* px = at(x, y);
    for (int c = 0; c < 3; ++c) {
      px[c] =
          std::uint8_t((color[std::size_t(c)] * coverage + px[c] * (255 - coverage) + 127) / 255);
    }
  }

 private:
  std::uint8_t* at(int x, int y) {
    return &image_.rgba[(std::size_t(y) * std::size_t(image_.width) + std::size_t(x)) * 4];
  }
  ProfilePlotImage& image_;
};

// The text's width in pixels at `scale` times the font's size.
int plotTextWidth(std::string_view text, const OverlayFont& font, int scale) {
  float width = 0;
  for (unsigned char c : text) width += font.glyph(c).advance;
  return int(std::lround(width)) * scale;
}

// `text` with its line's top-left corner at (left, top), each texel of the font's atlas a
// scale x scale block (nearest: crisp at any scale). Bytes are Latin-1 code points.
void drawPlotText(PlotCanvas& canvas, std::string_view text, int left, int top,
                  const OverlayFont& font, int scale) {
  const int atlas_w = font.atlasWidth(), atlas_h = font.atlasHeight();
  const std::vector<std::uint8_t>& atlas = font.atlas();
  float pen = 0;
  for (unsigned char c : text) {
    const OverlayGlyph& g = font.glyph(c);
    // The atlas coordinates are texel edges (ImGui packs glyphs on whole texels).
    const int tx0 = int(std::lround(g.u0 * float(atlas_w))),
              tx1 = int(std::lround(g.u1 * float(atlas_w)));
    const int ty0 = int(std::lround(g.v0 * float(atlas_h))),
              ty1 = int(std::lround(g.v1 * float(atlas_h)));
    const int gx = left + int(std::lround((pen + g.x0) * float(scale)));
    const int gy = top + int(std::lround(g.y0 * float(scale)));
    for (int ty = ty0; ty < ty1; ++ty) {
      for (int tx = tx0; tx < tx1; ++tx) {
        const int coverage = atlas[std::size_t(ty) * std::size_t(atlas_w) + std::size_t(tx)];
        for (int dy = 0; dy < scale; ++dy) {
          for (int dx = 0; dx < scale; ++dx) {
            canvas.blend(gx + (tx - tx0) * scale + dx, gy + (ty - ty0) * scale + dy,
                         kProfilePlotText, coverage);
          }
        }
      }
    }
    pen += g.advance;
  }
}

std::string plotMetres(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.2f m", value);
  return text;
}

}  // namespace

ProfilePlotImage drawProfilePlot(const HeightProfile& profile, double length,
                                 std::string_view title, const OverlayFont& font,
                                 const ProfilePlotLayout& layout) {
  assert(length > 0 && "drawProfilePlot: the section line's horizontal length must be > 0");
  assert(layout.plot_left >= 3 && layout.plot_top >= 3 && layout.plot_right + 3 <= layout.width &&
         layout.plot_bottom + 3 <= layout.height && layout.plot_right - layout.plot_left >= 2 &&
         layout.plot_bottom - layout.plot_top >= 2 && layout.text_scale >= 1 &&
         "drawProfilePlot: the data area and its axes must lie inside the picture");
  ProfilePlotImage image;
  image.width = layout.width;
  image.height = layout.height;
  image.rgba.resize(std::size_t(layout.width) * std::size_t(layout.height) * 4);
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    std::copy(kProfilePlotBackground.begin(), kProfilePlotBackground.end(), &image.rgba[i]);
  }
  const HeightRange heights = heightRange(profile);
  image.length = length;
  image.low = heights.low;
  image.high = heights.high;
  if (!(image.high - image.low >= 1e-9)) {
    const double middle = 0.5 * (image.low + image.high);
    image.low = middle - 0.5;
    image.high = middle + 0.5;
  }
  PlotCanvas canvas(image);
  const int scale = layout.text_scale;
  const int line = int(std::lround(font.lineHeight())) * scale;

  // The axes, left and below, three pixels clear of the data area (a dot reaches two pixels out:
  // 5 x 5 texels, about a quarter of a degree on a headset's panel, where the window's 2 x 2 dots
  // would be lost).
  for (int y = layout.plot_top - 3; y <= layout.plot_bottom + 2; ++y) {
    canvas.set(layout.plot_left - 3, y, kProfilePlotAxis);
  }
  for (int x = layout.plot_left - 3; x <= layout.plot_right + 2; ++x) {
    canvas.set(x, layout.plot_bottom + 2, kProfilePlotAxis);
  }

  // The dots.
  const double columns = layout.plot_right - layout.plot_left - 1;
  const double rows = layout.plot_bottom - layout.plot_top - 1;
  for (const ProfileSample& sample : profile.samples) {
    const double s = std::clamp(sample.station / length, 0.0, 1.0);
    const double z =
        std::clamp((sample.position.z - image.low) / (image.high - image.low), 0.0, 1.0);
    const int x = layout.plot_left + int(std::lround(s * columns));
    const int y = layout.plot_bottom - 1 - int(std::lround(z * rows));
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) canvas.set(x + dx, y + dy, kProfilePlotDot);
    }
  }

  // The labels: the title, the heights left of the vertical axis, the distances under the
  // horizontal one.
  drawPlotText(canvas, title, 12, 8, font, scale);
  const std::string high = plotMetres(image.high), low = plotMetres(image.low);
  const int label_right = layout.plot_left - 10;
  drawPlotText(canvas, high, label_right - plotTextWidth(high, font, scale), layout.plot_top - 4,
               font, scale);
  drawPlotText(canvas, low, label_right - plotTextWidth(low, font, scale),
               layout.plot_bottom + 4 - line, font, scale);
  const std::string end = plotMetres(length);
  drawPlotText(canvas, "0 m", layout.plot_left, layout.plot_bottom + 8, font, scale);
  drawPlotText(canvas, end, layout.plot_right - plotTextWidth(end, font, scale),
               layout.plot_bottom + 8, font, scale);
  return image;
}

}  // namespace parallax
