// A height profile's plot as an RGBA picture, drawn on the CPU: what the window's profile plot
// shows (viewer/measure_panel.cpp: the corridor's points as dots of distance along the line
// against height), with its axes and their ranges written beside them, for places that have no
// ImGui (the headset's panel, xr/profile_panel.h). No GL: a test reads the pixels.
//
// The picture (all in pixels, x right, y down, the top row first):
//   background  kProfilePlotBackground everywhere else, opaque.
//   data area   columns [plot_left, plot_right) x rows [plot_top, plot_bottom) of the layout. A
//               sample at station s (0 .. length) and height z (low .. high) is the 5 x 5 block
//               of kProfilePlotDot centred on
//                 column plot_left + round(s / length * (plot_right - plot_left - 1)),
//                 row    plot_bottom - 1 - round((z - low) / (high - low) * (plot_bottom - plot_top - 1)),
//               so the ends of each range land on the area's first and last pixel.
//   axes        kProfilePlotAxis: the column plot_left - 3 over rows plot_top - 3 .. plot_bottom + 2
//               and the row plot_bottom + 2 over columns plot_left - 3 .. plot_right + 2 (both
//               inclusive; clear of the dots' blocks, which reach 2 pixels out of the area).
//   labels      kProfilePlotText, in the overlay labels' font (render/overlay_font.h) at
//               `text_scale` times its size: the title at the top-left corner; the height range
//               ("%.2f m" of high and of low) right-aligned left of the vertical axis, at the top and
//               bottom of the data area; the distance range ("0 m" and "%.2f m" of length) under the
//               horizontal axis, at the area's left and right ends.
// The ranges: distance 0 .. the section line's horizontal length (a station's place in the plot
// is its place along the line: points missing at an end show as a gap, where the window stretches
// its plot from the first station to the last); heights from the lowest to the highest point
// (measure/height_profile.h heightRange), widened to 1 m about their middle when they span less
// than a nanometre (one point, a flat floor) rather than dividing by zero.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "measure/height_profile.h"
#include "render/overlay_font.h"

namespace parallax {

inline constexpr std::array<std::uint8_t, 4> kProfilePlotBackground{20, 20, 24, 255};
inline constexpr std::array<std::uint8_t, 4> kProfilePlotDot{255, 160, 50, 255};  // the window's
inline constexpr std::array<std::uint8_t, 4> kProfilePlotAxis{200, 200, 200, 255};
inline constexpr std::array<std::uint8_t, 4> kProfilePlotText{255, 255, 255, 255};

// The picture's size and where its data area is (see above). The default is sized for a panel
// about 30 degrees wide in a headset (about 20 pixels a degree) with the font at twice its 13
// pixels: 640 x 400.
struct ProfilePlotLayout {
  int width = 640, height = 400;
  int plot_left = 150, plot_top = 48, plot_right = 620, plot_bottom = 336;
  int text_scale = 2;
};

struct ProfilePlotImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4, the top row first
  // The axes' ranges, as drawn: distance 0 .. length, heights low .. high.
  double length = 0, low = 0, high = 0;
};

// The plot of `profile`, whose section line is `length` long horizontally (> 0: its stations run
// from 0 to it; measurement.h horizontalLength). Every sample is drawn (a picture drawn once; the
// window's thins them to 4000 dots a frame). `title` is written at the top-left (ASCII and
// Latin-1; what does not fit is cut at the picture's edge). The layout must leave the margins the
// labels need (asserted: the data area inside the picture with room for the axes).
ProfilePlotImage drawProfilePlot(const HeightProfile& profile, double length,
                                 std::string_view title, const OverlayFont& font,
                                 const ProfilePlotLayout& layout = {});

}  // namespace parallax
