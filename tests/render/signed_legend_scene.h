// The signed scene of the legend tests (test_scalar_legend.cpp: `render --legend`;
// test_viewer_panels.cpp: the viewer's legend over the window): M3C2 distances on a row of points
// seen from above, and the picture's oracle: every point's colour and every row of the legend's
// bar against Moreland's cool-warm ramp interpolated here.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "render/image_file.h"
#include "render/overlay_font.h"
#include "render/scalar_colors.h"
#include "render/scalar_legend.h"
#include "scalar_test_cloud.h"

namespace parallax::test {

using Rgb = std::array<int, 3>;

inline Rgb rgbOf(const Rgba8& c) {
  return {c.r, c.g, c.b};
}

// Moreland's cool-warm end and middle colours, linear in RGB between them.
inline Rgb coolWarm(double t) {
  const std::array<double, 3> cool{59, 76, 192}, mid{221, 221, 221}, warm{180, 4, 38};
  Rgb c;
  for (int i = 0; i < 3; ++i) {
    const double v = t <= 0.5 ? cool[i] + (mid[i] - cool[i]) * (t / 0.5)
                              : mid[i] + (warm[i] - mid[i]) * ((t - 0.5) / 0.5);
    c[i] = int(std::lround(v));
  }
  return c;
}

inline bool near(const Rgb& a, const Rgb& b, int tolerance) {
  for (int i = 0; i < 3; ++i) {
    if (std::abs(a[i] - b[i]) > tolerance) return false;
  }
  return true;
}

inline std::string text(const Rgb& c) {
  return std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]);
}

inline const std::vector<float> kSigned{
    -0.4f, -0.2f, -0.1f, 0.0f, 0.05f, 0.1f, 0.3f, std::numeric_limits<float>::quiet_NaN(), 1.0f};
constexpr int kWidth = 400, kHeight = 160;  // 20 pixels a unit (the ortho height: 8)
inline const Rgb kMagenta{255, 0, 255};
// The cloud from above, orthographic, the points along a row in the left half (x to the right),
// magenta behind: how `render` and the viewer's window draw the scene.
inline const std::string kSignedLook =
    "--width 400 --height 160 --point-size 3 --ortho --eye 9,0.1,10 --target 9,0.1,0 --up 0,1,0 "
    "--background 255,0,255 --rasterizer points";

inline std::string signedPly() {
  return floatScalarPly("m3c2_distance", kSigned);
}

inline Rgb pixel(const RgbaImage& image, int x, int y) {
  const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
  return {p[0], p[1], p[2]};
}

// The colours met left to right along the row of `image` (left of `right`) with the most
// pixels other than magenta, one per run of equal pixels.
inline std::vector<Rgb> pointColours(const RgbaImage& image, int right) {
  int best_row = 0, best = -1;
  for (int y = 0; y < image.height; ++y) {
    int count = 0;
    for (int x = 0; x < right; ++x) count += pixel(image, x, y) != kMagenta;
    if (count > best) best = count, best_row = y;
  }
  std::vector<Rgb> runs;
  bool in_run = false;
  for (int x = 0; x < right; ++x) {
    const Rgb c = pixel(image, x, best_row);
    const bool background = c == kMagenta;
    if (!background && (!in_run || runs.back() != c)) runs.push_back(c);
    in_run = !background;
  }
  return runs;
}

// The picture of the signed scene coloured by m3c2_distance through the cool-warm ramp over
// -reach .. reach, with its legend (render's PNG, or the viewer's window with the panel hidden):
// each point's colour, every pixel of the bar, the box behind it and the labels' white.
inline void expectSignedLegendPicture(const RgbaImage& image, double reach) {
  // The legend's place, from the layout of the same legend in the same font.
  const ScalarLegend legend =
      scalarLegend("m3c2_distance", ColorRamp::CoolWarm, {-reach, reach}, "m");
  const LegendLayout layout = legendLayout(legend, OverlayFont(), kWidth, kHeight);
  ASSERT_GT(layout.bar_height, 50);
  ASSERT_GT(layout.box_x, kWidth / 2);

  const std::vector<Rgb> points = pointColours(image, layout.box_x);
  ASSERT_EQ(points.size(), kSigned.size());
  for (std::size_t i = 0; i < kSigned.size(); ++i) {
    const double v = kSigned[i];
    const Rgb expected = std::isnan(v) ? Rgb{128, 128, 128}
                                       : coolWarm(std::clamp((v + reach) / (2 * reach), 0.0, 1.0));
    EXPECT_TRUE(near(points[i], expected, 1)) << i << ": " << text(points[i]);
  }

  // Every pixel of the bar: the ramp at 1 - row / (rows - 1), the maximum at the top.
  int wrong = 0;
  for (int row = 0; row < layout.bar_height; ++row) {
    const Rgb expected = coolWarm(1.0 - double(row) / double(layout.bar_height - 1));
    for (int x = layout.bar_x; x < layout.bar_x + layout.bar_width; ++x) {
      const Rgb got = pixel(image, x, layout.bar_y + row);
      if (!near(got, expected, 1) && wrong++ < 5) {
        ADD_FAILURE() << "bar row " << row << " x " << x << ": " << text(got) << ", expected "
                      << text(expected);
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  // The box behind: magenta darkened to 40 %, where no text is (its bottom-left corner).
  EXPECT_EQ(pixel(image, layout.box_x + 1, layout.box_y + layout.box_height - 2),
            (Rgb{102, 0, 102}));
  // Labels: white text within the box, right of the bar.
  int white = 0;
  for (int y = layout.box_y; y < layout.box_y + layout.box_height; ++y) {
    for (int x = layout.label_x; x < layout.box_x + layout.box_width; ++x) {
      white += pixel(image, x, y) == Rgb{255, 255, 255};
    }
  }
  EXPECT_GT(white, 100);
}

}  // namespace parallax::test
