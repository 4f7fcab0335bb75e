// The profile's plot as a picture (measure/profile_plot_image.h): each sample's dot where the
// test's own arithmetic on its distance and height puts it, the axes on their rows and columns,
// the ranges' labels beside them, nothing else drawn.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "measure/profile_plot_image.h"

namespace parallax {
namespace {

using Rgba = std::array<std::uint8_t, 4>;

Rgba pixelOf(const ProfilePlotImage& image, int x, int y) {
  const std::uint8_t* p = &image.rgba[(std::size_t(y) * std::size_t(image.width) + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

ProfileSample sampleAt(double station, double height) {
  ProfileSample sample;
  sample.station = station;
  sample.position = {512000.0 + station, 5400000.0, height};
  return sample;
}

// Four samples on a line 8 m long at UTM-size heights 312..314.5: the lowest at the line's start,
// the highest at its end.
HeightProfile fourSamples() {
  HeightProfile profile;
  profile.samples = {sampleAt(0.0, 312.0), sampleAt(2.0, 313.0), sampleAt(5.0, 312.5),
                     sampleAt(8.0, 314.5)};
  return profile;
}

// The layout's data area written out: 640 x 400, columns 150..619, rows 48..335.
constexpr int kLeft = 150, kTop = 48, kRight = 620, kBottom = 336;

// The centre pixel of a sample's dot, from the station and height alone: 0..8 m over the 470
// columns' centres, 312..314.5 m over the 288 rows' (the first row the top).
std::array<int, 2> expectedDot(double station, double height) {
  const double x = kLeft + station / 8.0 * (kRight - kLeft - 1);
  const double y = (kBottom - 1) - (height - 312.0) / 2.5 * (kBottom - kTop - 1);
  return {int(std::lround(x)), int(std::lround(y))};
}

TEST(ProfilePlotImage, EachSampleIsADotWhereItsDistanceAndHeightPutIt) {
  const OverlayFont font;
  const ProfilePlotImage image = drawProfilePlot(fourSamples(), 8.0, "profile 1", font);
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 400);
  ASSERT_EQ(image.rgba.size(), 640u * 400u * 4u);
  EXPECT_EQ(image.length, 8.0);
  EXPECT_EQ(image.low, 312.0);
  EXPECT_EQ(image.high, 314.5);
  const Rgba dot{255, 160, 50, 255}, background{20, 20, 24, 255};
  int dots = 0;
  for (const ProfileSample& s : fourSamples().samples) {
    const auto [x, y] = expectedDot(s.station, s.position.z);
    // The 5 x 5 block around the centre, and the background just outside it (left and right:
    // no two samples are near each other).
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        EXPECT_EQ(pixelOf(image, x + dx, y + dy), dot) << "sample at " << s.station << " m";
      }
    }
    EXPECT_NE(pixelOf(image, x - 3, y), dot) << "sample at " << s.station << " m";
    EXPECT_NE(pixelOf(image, x + 3, y), dot) << "sample at " << s.station << " m";
    EXPECT_NE(pixelOf(image, x, y - 3), dot) << "sample at " << s.station << " m";
    EXPECT_NE(pixelOf(image, x, y + 3), dot) << "sample at " << s.station << " m";
    ++dots;
  }
  EXPECT_EQ(dots, 4);
  // The ends of the ranges: the first sample at the data area's bottom-left pixel, the last at
  // its top-right one.
  EXPECT_EQ(expectedDot(0.0, 312.0), (std::array<int, 2>{kLeft, kBottom - 1}));
  EXPECT_EQ(expectedDot(8.0, 314.5), (std::array<int, 2>{kRight - 1, kTop}));
  // Every dot pixel in the picture is one of those blocks.
  int dot_pixels = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) dot_pixels += pixelOf(image, x, y) == dot;
  }
  EXPECT_EQ(dot_pixels, 4 * 25);
  EXPECT_EQ(pixelOf(image, (kLeft + kRight) / 2, kTop + 5), background);
}

TEST(ProfilePlotImage, AxesRunLeftOfAndUnderTheDataAreaAndTheirRangesAreLabelled) {
  const OverlayFont font;
  const ProfilePlotImage image = drawProfilePlot(fourSamples(), 8.0, "profile 1", font);
  const Rgba axis{200, 200, 200, 255};
  for (int y = kTop - 3; y <= kBottom + 2; ++y) EXPECT_EQ(pixelOf(image, kLeft - 3, y), axis) << y;
  for (int x = kLeft - 3; x <= kRight + 2; ++x)
    EXPECT_EQ(pixelOf(image, x, kBottom + 2), axis) << x;
  EXPECT_NE(pixelOf(image, kLeft - 3, kTop - 4), axis);
  EXPECT_NE(pixelOf(image, kRight + 3, kBottom + 2), axis);

  // Text: white where a glyph covers a pixel wholly (the font's coverage is 0 or 255 inside most
  // strokes), grey at a stroke's edge. Where it is, region by region.
  struct Box {
    int count = 0, x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  };
  const auto textIn = [&](int x0, int y0, int x1, int y1) {
    Box box;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Rgba p = pixelOf(image, x, y);
        if (p[0] != 255 || p[1] != 255 || p[2] != 255) continue;
        ++box.count;
        box.x0 = std::min(box.x0, x), box.y0 = std::min(box.y0, y);
        box.x1 = std::max(box.x1, x), box.y1 = std::max(box.y1, y);
      }
    }
    return box;
  };
  // The text's width at twice the font's size: its advances summed.
  const auto widthOf = [&](const char* text) {
    float w = 0;
    for (const char* c = text; *c; ++c) w += font.glyph(unsigned(*c)).advance;
    return 2.0 * w;
  };
  // "314.50 m" and "312.00 m" end 10 pixels left of the data area, at its top and bottom.
  const Box high = textIn(0, kTop - 10, kLeft - 4, kTop + 26);
  const Box low = textIn(0, kBottom - 30, kLeft - 4, kBottom + 6);
  ASSERT_GT(high.count, 40);
  ASSERT_GT(low.count, 40);
  EXPECT_NEAR(high.x1, kLeft - 10 - 1, 3);
  EXPECT_NEAR(low.x1, kLeft - 10 - 1, 3);
  EXPECT_NEAR(high.x1 - high.x0 + 1, widthOf("314.50 m"), 4);
  EXPECT_NEAR(low.x1 - low.x0 + 1, widthOf("312.00 m"), 4);
  // "0 m" under the axis from the area's left end; "8.00 m" ending at its right end.
  const Box zero = textIn(kLeft - 2, kBottom + 4, kLeft + 80, image.height - 1);
  const Box end = textIn(kRight - 120, kBottom + 4, image.width - 1, image.height - 1);
  ASSERT_GT(zero.count, 20);
  ASSERT_GT(end.count, 30);
  EXPECT_NEAR(zero.x0, kLeft, 3);
  EXPECT_NEAR(zero.x1 - zero.x0 + 1, widthOf("0 m"), 4);
  EXPECT_NEAR(end.x1, kRight - 1, 3);
  EXPECT_NEAR(end.x1 - end.x0 + 1, widthOf("8.00 m"), 4);
  // The title at the top-left corner; no text inside the data area.
  const Box title = textIn(0, 0, image.width - 1, kTop - 12);
  ASSERT_GT(title.count, 40);
  EXPECT_NEAR(title.x0, 12, 3);
  EXPECT_EQ(textIn(kLeft, kTop, kRight - 1, kBottom - 1).count, 0);
}

TEST(ProfilePlotImage, AFlatProfileSpansAMetreAboutItsHeight) {
  const OverlayFont font;
  HeightProfile profile;
  profile.samples = {sampleAt(1.0, 100.0), sampleAt(3.0, 100.0)};
  const ProfilePlotImage image = drawProfilePlot(profile, 4.0, "flat", font);
  EXPECT_EQ(image.low, 99.5);
  EXPECT_EQ(image.high, 100.5);
  // Height 100 is the middle of 99.5..100.5: row 335 - round(0.5 * 287) = 191; station 1 of 4
  // is column 150 + round(0.25 * 469) = 267.
  EXPECT_EQ(pixelOf(image, 267, 191), (Rgba{255, 160, 50, 255}));
  EXPECT_EQ(pixelOf(image, 150 + int(std::lround(0.75 * 469)), 191), (Rgba{255, 160, 50, 255}));
}

}  // namespace
}  // namespace parallax
