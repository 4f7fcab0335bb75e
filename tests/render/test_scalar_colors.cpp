// Scalar attributes shown with a colour ramp (render/scalar_colors.h): the ramps against colours
// computed here from their definitions (matplotlib's published viridis colours, the piecewise
// "jet" rainbow, grey), and `parallax render --color ATTRIBUTE` end to end through both
// rasterizers, the pixels of each point against the same independent colours.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "render/image_file.h"
#include "render/scalar_colors.h"
#include "scalar_test_cloud.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::readText;
using test::runWithoutLeakCheck;

using Rgb = std::array<int, 3>;

Rgb rgbOf(const Rgba8& c) {
  return {c.r, c.g, c.b};
}

int channel(double unit) {
  return int(std::lround(255.0 * unit));
}

Rgb grey(double t) {
  return {channel(t), channel(t), channel(t)};
}

// MATLAB's jet written as its pieces (the product computes clamp(1.5 - |4t - c|)).
Rgb jet(double t) {
  const double r = t < 0.375 ? 0 : t < 0.625 ? 4 * t - 1.5 : t < 0.875 ? 1 : 4.5 - 4 * t;
  const double g = t < 0.125   ? 0
                   : t < 0.375 ? 4 * t - 0.5
                   : t < 0.625 ? 1
                   : t < 0.875 ? 3.5 - 4 * t
                               : 0;
  const double b = t < 0.125 ? 0.5 + 4 * t : t < 0.375 ? 1 : t < 0.625 ? 2.5 - 4 * t : 0;
  return {channel(r), channel(g), channel(b)};
}

Rgb hex(unsigned value) {
  return {int(value >> 16), int((value >> 8) & 0xff), int(value & 0xff)};
}

// Every channel within `tolerance` (the jet's pieces and the product's formula round 0.5 apart
// differently where t is not a binary fraction).
bool near(const Rgb& a, const Rgb& b, int tolerance) {
  for (int i = 0; i < 3; ++i) {
    if (std::abs(a[i] - b[i]) > tolerance) return false;
  }
  return true;
}

TEST(ColorRamp, ViridisHasMatplotlibsColoursAtItsQuarters) {
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 0.0)), hex(0x440154));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 0.25)), hex(0x3b528b));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 0.5)), hex(0x21918c));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 0.75)), hex(0x5ec962));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 1.0)), hex(0xfde725));
  // Halfway between the first two stops: their mean, rounded.
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 0.125)), (Rgb{64, 42, 112}));
  // Outside [0, 1]: the ends.
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, -3.0)), hex(0x440154));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Viridis, 7.0)), hex(0xfde725));
}

TEST(ColorRamp, RainbowAndGreyFollowTheirDefinitions) {
  for (int i = 0; i <= 64; ++i) {
    const double t = i / 64.0;  // binary fractions: the two forms round alike
    EXPECT_EQ(rgbOf(rampColor(ColorRamp::Rainbow, t)), jet(t)) << t;
    EXPECT_EQ(rgbOf(rampColor(ColorRamp::Grey, t)), grey(t)) << t;
  }
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Rainbow, 0.0)), (Rgb{0, 0, 128}));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Rainbow, 1.0)), (Rgb{128, 0, 0}));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::Rainbow, 0.5)), (Rgb{128, 255, 128}));
}

TEST(ColorRamp, NamesParseAndUnknownNamesDoNot) {
  EXPECT_EQ(parseColorRamp("viridis"), ColorRamp::Viridis);
  EXPECT_EQ(parseColorRamp("rainbow"), ColorRamp::Rainbow);
  EXPECT_EQ(parseColorRamp("jet"), ColorRamp::Rainbow);
  EXPECT_EQ(parseColorRamp("grey"), ColorRamp::Grey);
  EXPECT_EQ(parseColorRamp("gray"), ColorRamp::Grey);
  EXPECT_FALSE(parseColorRamp("Viridis"));
  EXPECT_EQ(parseColorRamp("coolwarm"), ColorRamp::CoolWarm);
  EXPECT_EQ(parseColorRamp("diverging"), ColorRamp::CoolWarm);
  EXPECT_EQ(colorRampNames(), "viridis|rainbow|grey|coolwarm");
}

// The distance values of the test cloud, one point each at x = 0, 1, 2, ...
const std::vector<float> kDistances{0, 1, 2, 3, 4, 6, 7, std::numeric_limits<float>::quiet_NaN(),
                                    20};

PointCloud cloudWithDistance() {
  return cloudWithFloatScalar("distance", kDistances);
}

TEST(PaintScalarField, AutoRangeSkipsNaNAndNaNIsGrey) {
  PointCloud cloud = cloudWithDistance();
  const ScalarRange range = paintScalarField(cloud, {.field = "distance", .ramp = ColorRamp::Grey});
  EXPECT_EQ(range, (ScalarRange{0.0, 20.0}));
  ASSERT_EQ(cloud.colors.size(), cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const Rgb expected =
        std::isnan(kDistances[i]) ? Rgb{128, 128, 128} : grey(kDistances[i] / 20.0);
    EXPECT_EQ(rgbOf(cloud.colors[i]), expected) << i;
  }
}

TEST(PaintScalarField, GivenRangeClampsAndBadInputIsAnError) {
  PointCloud cloud = cloudWithDistance();
  paintScalarField(cloud,
                   {.field = "distance", .ramp = ColorRamp::Grey, .range = ScalarRange{2.0, 6.0}});
  EXPECT_EQ(rgbOf(cloud.colors[0]), grey(0.0));   // 0 < 2: the low end
  EXPECT_EQ(rgbOf(cloud.colors[3]), grey(0.25));  // 3
  EXPECT_EQ(rgbOf(cloud.colors[8]), grey(1.0));   // 20 > 6: the high end
  try {
    paintScalarField(cloud, {.field = "curvature"});
    FAIL() << "an attribute the cloud lacks was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'curvature'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scalar fields: distance"), std::string::npos) << e.what();
  }
  EXPECT_THROW(paintScalarField(cloud, {.field = "distance", .range = ScalarRange{3.0, 3.0}}),
               std::invalid_argument);
}

// --- `parallax render --color distance`, end to end -----------------------------------------

// The test cloud as a binary PLY (x y z double, distance float: NaN too).
std::string distancePly() {
  return floatScalarPly("distance", kDistances);
}

// The colours met along the image's row `row`, left to right, one per run of equal pixels other
// than the background, magenta, which no ramp makes (the points are 5 pixels apart and 3 wide:
// background between them).
std::vector<Rgb> runsAlongRow(const RgbaImage& image, int row) {
  std::vector<Rgb> runs;
  bool in_run = false;
  for (int x = 0; x < image.width; ++x) {
    const std::uint8_t* p = &image.pixels[(std::size_t(row) * image.width + x) * 4];
    const Rgb c{p[0], p[1], p[2]};
    const bool background = c == Rgb{255, 0, 255};
    if (!background && (!in_run || runs.back() != c)) runs.push_back(c);
    in_run = !background;
  }
  return runs;
}

struct RenderRun {
  int rc = 0;
  std::string log;
  std::vector<Rgb> runs;
};

// Renders the cloud from above, orthographic (8 units over 40 rows: 5 pixels a unit), x to the
// right, with `color_options`.
RenderRun renderDistances(const TempDir& dir, const std::string& rasterizer,
                          const std::string& color_options) {
  const auto ply = dir.write("distance.ply", distancePly());
  const auto png = dir / ("out-" + rasterizer + ".png");
  const auto log = dir / "log";
  const std::string command =
      std::string(PARALLAX_EXECUTABLE) + " render '" + ply.string() + "' -o '" + png.string() +
      "' --width 160 --height 40 --point-size 3 --ortho"
      " --eye 4,0.1,10 --target 4,0.1,0 --up 0,1,0 --background 255,0,255 --rasterizer " +
      rasterizer + " " + color_options + " 2>'" + log.string() + "'";
  RenderRun result;
  result.rc = runWithoutLeakCheck(command);
  result.log = readText(log);
  if (result.rc == 0) result.runs = runsAlongRow(readPng(png), 20);
  return result;
}

class RenderScalarColors : public ::testing::TestWithParam<const char*> {};

TEST_P(RenderScalarColors, GreyWithAGivenRangeGivesEachPointItsColour) {
  TempDir dir;
  const RenderRun r = renderDistances(dir, GetParam(),
                                      "--color distance --color-ramp grey "
                                      "--color-range 1,9");
  ASSERT_EQ(r.rc, 0) << r.log;
  std::vector<Rgb> expected;
  for (float d : kDistances) {
    expected.push_back(std::isnan(d) ? Rgb{128, 128, 128}
                                     : grey(std::clamp((double(d) - 1.0) / 8.0, 0.0, 1.0)));
  }
  EXPECT_EQ(r.runs, expected);
}

TEST_P(RenderScalarColors, RainbowOverTheAttributesOwnRange) {
  TempDir dir;
  const RenderRun r = renderDistances(dir, GetParam(), "--color distance --color-ramp rainbow");
  ASSERT_EQ(r.rc, 0) << r.log;
  EXPECT_NE(r.log.find("distance from 0 to 20, rainbow ramp"), std::string::npos) << r.log;
  ASSERT_EQ(r.runs.size(), kDistances.size());
  for (std::size_t i = 0; i < kDistances.size(); ++i) {
    const Rgb expected = std::isnan(kDistances[i]) ? Rgb{128, 128, 128} : jet(kDistances[i] / 20.0);
    EXPECT_TRUE(near(r.runs[i], expected, 1))
        << i << ": " << r.runs[i][0] << ' ' << r.runs[i][1] << ' ' << r.runs[i][2];
  }
}

TEST_P(RenderScalarColors, ViridisEndsAndMiddle) {
  TempDir dir;
  const RenderRun r = renderDistances(dir, GetParam(), "--color distance --color-range 0,6");
  ASSERT_EQ(r.rc, 0) << r.log;
  ASSERT_EQ(r.runs.size(), kDistances.size());
  EXPECT_EQ(r.runs[0], hex(0x440154));  // 0
  EXPECT_EQ(r.runs[3], hex(0x21918c));  // 3, the middle
  EXPECT_EQ(r.runs[5], hex(0xfde725));  // 6
  EXPECT_EQ(r.runs[8], hex(0xfde725));  // 20, clamped
}

INSTANTIATE_TEST_SUITE_P(BothRasterizers, RenderScalarColors,
                         ::testing::Values("points", "compute"));

TEST(RenderScalarColorsErrors, UnknownAttributeRampAndRangeAreNamed) {
  TempDir dir;
  RenderRun r = renderDistances(dir, "points", "--color curvature");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("no attribute 'curvature'"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("scalar fields: distance"), std::string::npos) << r.log;
  r = renderDistances(dir, "points", "--color distance --color-ramp hot");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("unknown ramp 'hot' (use viridis|rainbow|grey|coolwarm)"), std::string::npos)
      << r.log;
  r = renderDistances(dir, "points", "--color distance --color-range 5,1");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("MIN below MAX"), std::string::npos) << r.log;
  r = renderDistances(dir, "points", "--color elevation --color-range 0,1");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("not to --color elevation"), std::string::npos) << r.log;
}

}  // namespace
}  // namespace parallax::test
