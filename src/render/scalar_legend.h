// The legend of a scalar colouring (render/scalar_colors.h): a vertical ramp bar at the right of
// a picture, the maximum at its top and the minimum at its bottom, ticks at round values between,
// each labelled with its value, and a title naming the field and its unit.
//
// One layout, two painters: `paintScalarLegend` draws it into an RGBA image on the CPU (`parallax
// render --legend`), and the viewer draws the same layout's bar, ticks and text through Dear
// ImGui's draw list. Both take the bar's colours from `legendBarColor` and the label positions
// from the layout, so a PNG and the window show the same legend.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "render/image_file.h"
#include "render/overlay_font.h"
#include "render/overlay_geometry.h"
#include "render/scalar_colors.h"

namespace parallax {

struct LegendTick {
  double value = 0.0;
  std::string text;  // the value as printed, with the unit at the two ends
};

struct ScalarLegend {
  std::string title;  // "m3c2_distance [m]"; the field alone where the unit is empty
  ColorRamp ramp = ColorRamp::Viridis;
  ScalarRange range;
  std::vector<LegendTick> ticks;  // the range's ends first (min, max), then round values between
};

// The unit a field's values are in, where the field is one Parallax writes as a length (the
// distance and height columns of `process`: distance, height_above_ground, m3c2_distance,
// m3c2_uncertainty, m3c2_std1, m3c2_std2): `length_unit`; "" for any other field (intensity,
// curvature, counts), whose values have no unit Parallax knows.
std::string fieldUnit(std::string_view field, std::string_view length_unit);

// The legend of `field` shown with `ramp` over `range` (min below max, or equal: one tick):
// ticks at the multiples of a 1, 2 or 5 times a power of ten step giving at most `max_ticks`
// inside the range, less those within a third of a step of an end; the ends printed with the
// unit (where `unit` is not empty).
ScalarLegend scalarLegend(const std::string& field, ColorRamp ramp, const ScalarRange& range,
                          const std::string& unit, int max_ticks = 6);

// Where the legend goes in a picture of `width` x `height` pixels (rows top first): the bar, its
// tick labels to its right and the title above, inside a box of a translucent dark background
// at the right edge. All in whole pixels; a picture too small for it gives an empty bar (height
// 0) and the painters draw nothing.
struct LegendLayout {
  int box_x = 0, box_y = 0, box_width = 0, box_height = 0;
  int bar_x = 0, bar_y = 0, bar_width = 0, bar_height = 0;  // bar_y: its top row
  int title_x = 0, title_y = 0;                             // the title's top-left pixel
  int label_x = 0;                                          // the labels' left column
};
LegendLayout legendLayout(const ScalarLegend& legend, const OverlayGlyphs& font, int width,
                          int height);

// The colour of the bar's row `row` (0: its top, the maximum; bar_height - 1: the minimum): the
// ramp at 1 - row / (bar_height - 1).
Rgba8 legendBarColor(const ScalarLegend& legend, const LegendLayout& layout, int row);

// The bar's row that shows `value` (the nearest; values outside the range at the ends).
int legendRowOf(const ScalarLegend& legend, const LegendLayout& layout, double value);

// Width in pixels of `text` in `font` (the sum of advances).
float textWidth(const OverlayGlyphs& font, std::string_view text);

// Paints the legend into `image` (rows top first): the box blended over the picture, the bar,
// a tick mark and a label per tick, the title. `font` is render/overlay_font.h's font and its
// coverage atlas.
void paintScalarLegend(RgbaImage& image, const ScalarLegend& legend, const OverlayFont& font);

}  // namespace parallax
