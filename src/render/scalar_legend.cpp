#include "render/scalar_legend.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace parallax {

namespace {

constexpr int kMargin = 10;    // from the picture's edges
constexpr int kPadding = 6;    // inside the box
constexpr int kBarWidth = 16;  // pixels
constexpr int kMaxBarHeight = 240;
constexpr int kMinBarHeight = 16;
constexpr int kTickLength = 4;  // the mark right of the bar
constexpr float kBoxOpacity = 0.6f;

// The fields `process` writes in the cloud's length unit.
constexpr std::array<std::string_view, 6> kLengthFields{"distance",      "height_above_ground",
                                                        "m3c2_distance", "m3c2_uncertainty",
                                                        "m3c2_std1",     "m3c2_std2"};

// A 1, 2 or 5 times a power of ten step at least `raw`.
double niceStep(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw * (1.0 - 1e-12)) return m * power;
  }
  return 10.0 * power;
}

// The value with as many decimals as the step needs (none for steps of 1 and more).
std::string formatValue(double value, double step) {
  const int decimals = step >= 1.0 ? 0 : int(std::ceil(-std::log10(step) - 1e-9));
  if (value == 0.0 || std::abs(value) < step * 1e-9) value = 0.0;  // no "-0"
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", std::clamp(decimals, 0, 12), value);
  return text;
}

std::uint8_t blend(std::uint8_t under, float over, float alpha) {
  return std::uint8_t(std::lround(float(under) * (1.0f - alpha) + over * alpha));
}

void blendPixel(RgbaImage& image, int x, int y, std::array<float, 3> color, float alpha) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height || alpha <= 0.0f) return;
  std::uint8_t* p = &image.pixels[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4];
  for (int c = 0; c < 3; ++c) p[c] = blend(p[c], color[std::size_t(c)], alpha);
  p[3] = 255;
}

// Draws `text` with its top-left at (x, y), white, each pixel blended by the atlas's coverage.
// ProggyClean's glyphs are whole pixels in the atlas, so nearest sampling is exact.
void paintText(RgbaImage& image, const OverlayFont& font, std::string_view text, float x, int y) {
  for (const unsigned char c : text) {
    const OverlayGlyph& g = font.glyph(c);
    const int qx0 = int(std::lround(x + g.x0)), qx1 = int(std::lround(x + g.x1));
    const int qy0 = y + int(std::lround(g.y0)), qy1 = y + int(std::lround(g.y1));
    for (int py = qy0; py < qy1; ++py) {
      for (int px = qx0; px < qx1; ++px) {
        const float u = g.u0 + (float(px - qx0) + 0.5f) / float(qx1 - qx0) * (g.u1 - g.u0);
        const float v = g.v0 + (float(py - qy0) + 0.5f) / float(qy1 - qy0) * (g.v1 - g.v0);
        const int ax = std::clamp(int(u * float(font.atlasWidth())), 0, font.atlasWidth() - 1);
        const int ay = std::clamp(int(v * float(font.atlasHeight())), 0, font.atlasHeight() - 1);
        const float coverage =
            float(
                font.atlas()[std::size_t(ay) * std::size_t(font.atlasWidth()) + std::size_t(ax)]) /
            255.0f;
        blendPixel(image, px, py, {255, 255, 255}, coverage);
      }
    }
    x += g.advance;
  }
}

}  // namespace

std::string fieldUnit(std::string_view field, std::string_view length_unit) {
  return std::find(kLengthFields.begin(), kLengthFields.end(), field) != kLengthFields.end()
             ? std::string(length_unit)
             : std::string();
}

ScalarLegend scalarLegend(const std::string& field, ColorRamp ramp, const ScalarRange& range,
                          const std::string& unit, int max_ticks) {
  ScalarLegend legend;
  legend.title = unit.empty() ? field : field + " [" + unit + "]";
  legend.ramp = ramp;
  legend.range = range;
  const double span = range.max - range.min;
  const double step = span > 0.0 ? niceStep(span / double(std::max(max_ticks, 1))) : 1.0;
  // The ends take one decimal more than the round ticks: they are percentiles or the user's.
  const std::string suffix = unit.empty() ? "" : " " + unit;
  legend.ticks.push_back({range.min, formatValue(range.min, step / 10.0) + suffix});
  if (!(span > 0.0)) return legend;
  legend.ticks.push_back({range.max, formatValue(range.max, step / 10.0) + suffix});
  for (double k = std::ceil(range.min / step); k * step <= range.max; k += 1.0) {
    const double value = k * step;
    if (value - range.min < step / 3.0 || range.max - value < step / 3.0) continue;
    legend.ticks.push_back({value, formatValue(value, step)});
  }
  return legend;
}

float textWidth(const OverlayGlyphs& font, std::string_view text) {
  float width = 0.0f;
  for (const unsigned char c : text) width += font.glyph(c).advance;
  return width;
}

LegendLayout legendLayout(const ScalarLegend& legend, const OverlayGlyphs& font, int width,
                          int height) {
  LegendLayout layout;
  const int line = int(std::ceil(font.lineHeight()));
  float labels = 0.0f;
  for (const auto& tick : legend.ticks) labels = std::max(labels, textWidth(font, tick.text));
  const int content_width = std::max(int(std::ceil(textWidth(font, legend.title))),
                                     kBarWidth + 2 * kTickLength + int(std::ceil(labels)));
  layout.box_width = content_width + 2 * kPadding;
  // Title, a gap of half a line (the top label is centred on the bar's first row), the bar, half
  // a line below it for the bottom label.
  const int above_bar = kPadding + line + line / 2 + 2;
  const int below_bar = line / 2 + kPadding;
  const int bar_height = std::min(kMaxBarHeight, height - 2 * kMargin - above_bar - below_bar);
  layout.box_x = width - kMargin - layout.box_width;
  if (bar_height < kMinBarHeight || layout.box_x < 0) return LegendLayout{};
  layout.box_y = kMargin;
  layout.box_height = above_bar + bar_height + below_bar;
  layout.title_x = layout.box_x + kPadding;
  layout.title_y = layout.box_y + kPadding;
  layout.bar_x = layout.box_x + kPadding;
  layout.bar_y = layout.box_y + above_bar;
  layout.bar_width = kBarWidth;
  layout.bar_height = bar_height;
  layout.label_x = layout.bar_x + kBarWidth + 2 * kTickLength;
  return layout;
}

Rgba8 legendBarColor(const ScalarLegend& legend, const LegendLayout& layout, int row) {
  const double t = layout.bar_height > 1 ? 1.0 - double(row) / double(layout.bar_height - 1) : 0.5;
  return rampColor(legend.ramp, t);
}

int legendRowOf(const ScalarLegend& legend, const LegendLayout& layout, double value) {
  const double t = rampPosition(value, legend.range);
  return int(std::lround((1.0 - t) * double(layout.bar_height - 1)));
}

void paintScalarLegend(RgbaImage& image, const ScalarLegend& legend, const OverlayFont& font) {
  const LegendLayout layout = legendLayout(legend, font, image.width, image.height);
  if (layout.bar_height == 0) return;
  for (int y = layout.box_y; y < layout.box_y + layout.box_height; ++y) {
    for (int x = layout.box_x; x < layout.box_x + layout.box_width; ++x) {
      blendPixel(image, x, y, {0, 0, 0}, kBoxOpacity);
    }
  }
  for (int row = 0; row < layout.bar_height; ++row) {
    const Rgba8 c = legendBarColor(legend, layout, row);
    for (int x = layout.bar_x; x < layout.bar_x + layout.bar_width; ++x) {
      blendPixel(image, x, layout.bar_y + row, {float(c.r), float(c.g), float(c.b)}, 1.0f);
    }
  }
  const int line = int(std::ceil(font.lineHeight()));
  for (const auto& tick : legend.ticks) {
    const int y = layout.bar_y + legendRowOf(legend, layout, tick.value);
    for (int x = layout.bar_x + layout.bar_width; x < layout.label_x - kTickLength / 2; ++x) {
      blendPixel(image, x, y, {255, 255, 255}, 1.0f);
    }
    paintText(image, font, tick.text, float(layout.label_x), y - line / 2);
  }
  paintText(image, font, legend.title, float(layout.title_x), layout.title_y);
}

}  // namespace parallax
