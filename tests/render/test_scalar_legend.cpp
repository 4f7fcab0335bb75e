// The diverging ramp, the automatic range from percentiles, and the legend
// (render/scalar_legend.h): the ramp against Moreland's three colours interpolated here, the
// percentiles against ranks counted here, and `parallax render --color m3c2_distance --legend`
// end to end: each point's pixels and every pixel of the legend's bar against colours computed
// in the test from the values and the bar's rows.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "render/image_file.h"
#include "render/overlay_font.h"
#include "render/scalar_colors.h"
#include "render/scalar_legend.h"
#include "scalar_test_cloud.h"
#include "signed_legend_scene.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::readText;
using test::runWithoutLeakCheck;

TEST(CoolWarmRamp, MorelandsColoursAtTheEndsAndTheMiddleAndLinearBetween) {
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::CoolWarm, 0.0)), (Rgb{59, 76, 192}));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::CoolWarm, 0.5)), (Rgb{221, 221, 221}));
  EXPECT_EQ(rgbOf(rampColor(ColorRamp::CoolWarm, 1.0)), (Rgb{180, 4, 38}));
  for (int i = 0; i <= 64; ++i) {
    const double t = i / 64.0;
    EXPECT_TRUE(near(rgbOf(rampColor(ColorRamp::CoolWarm, t)), coolWarm(t), 1)) << t;
  }
  EXPECT_TRUE(isDiverging(ColorRamp::CoolWarm));
  EXPECT_FALSE(isDiverging(ColorRamp::Viridis));
}

// A cloud whose "m3c2_distance" holds `values`, one point each at x = 0, 1, 2, ...
PointCloud cloudWith(const std::vector<float>& values) {
  return cloudWithFloatScalar("m3c2_distance", values);
}

TEST(ScalarPercentiles, NearestRankOverTheFiniteValues) {
  // 0, 1, ..., 100 shuffled by a stride, a NaN and an infinity that do not count.
  std::vector<float> values;
  for (int i = 0; i <= 100; ++i) values.push_back(float((i * 37) % 101));
  values.push_back(std::numeric_limits<float>::quiet_NaN());
  values.push_back(std::numeric_limits<float>::infinity());
  const PointCloud cloud = cloudWith(values);
  EXPECT_EQ(scalarPercentileRange(cloud, "m3c2_distance", {0, 100}), (ScalarRange{0, 100}));
  EXPECT_EQ(scalarPercentileRange(cloud, "m3c2_distance", {2, 98}), (ScalarRange{2, 98}));
  EXPECT_EQ(scalarPercentileRange(cloud, "m3c2_distance", {25, 25}), (ScalarRange{25, 25}));
  // 10 values: ranks round(0.05 * 9) = 0 and round(0.95 * 9) = 9 (8.55).
  const PointCloud ten = cloudWith({9, 8, 7, 6, 5, 4, 3, 2, 1, 0});
  EXPECT_EQ(scalarPercentileRange(ten, "m3c2_distance", {5, 95}), (ScalarRange{0, 9}));
  EXPECT_EQ(scalarPercentileRange(ten, "m3c2_distance", {10, 90}), (ScalarRange{1, 8}));
  EXPECT_THROW(scalarPercentileRange(ten, "m3c2_distance", {50, 40}), std::invalid_argument);
  EXPECT_THROW(scalarPercentileRange(ten, "m3c2_distance", {-1, 40}), std::invalid_argument);
  EXPECT_THROW(scalarPercentileRange(ten, "curvature", {0, 100}), std::invalid_argument);
  const PointCloud none = cloudWith({std::numeric_limits<float>::quiet_NaN()});
  EXPECT_EQ(scalarPercentileRange(none, "m3c2_distance", {2, 98}), std::nullopt);
}

TEST(ScalarAutoRange, ADivergingRampIsCentredOnZeroWhereTheValuesStraddleIt) {
  const PointCloud cloud = cloudWith({-0.4f, -0.2f, -0.1f, 0.0f, 0.05f, 0.1f, 0.3f, 1.0f});
  ScalarColoring coloring{.field = "m3c2_distance", .ramp = ColorRamp::CoolWarm};
  EXPECT_EQ(scalarAutoRange(cloud, coloring), (ScalarRange{-1.0, 1.0}));
  coloring.percentiles = {10, 90};  // ranks 1 and 6 of 8: -0.2 and 0.3
  EXPECT_EQ(scalarAutoRange(cloud, coloring), (ScalarRange{double(-0.3f), double(0.3f)}));
  coloring.ramp = ColorRamp::Viridis;  // not diverging: the percentiles as they are
  EXPECT_EQ(scalarAutoRange(cloud, coloring), (ScalarRange{double(-0.2f), double(0.3f)}));
  const PointCloud positive = cloudWith({1, 2, 3});
  EXPECT_EQ(scalarAutoRange(positive, {.field = "m3c2_distance", .ramp = ColorRamp::CoolWarm}),
            (ScalarRange{1, 3}));
}

TEST(ScalarLegendTicks, RoundValuesBetweenTheEndsWhichCarryTheUnit) {
  const ScalarLegend legend = scalarLegend("m3c2_distance", ColorRamp::CoolWarm, {-0.3, 0.3},
                                           fieldUnit("m3c2_distance", "m"));
  EXPECT_EQ(legend.title, "m3c2_distance [m]");
  std::vector<std::string> texts;
  for (const auto& tick : legend.ticks) texts.push_back(tick.text);
  EXPECT_EQ(texts,
            (std::vector<std::string>{"-0.30 m", "0.30 m", "-0.2", "-0.1", "0.0", "0.1", "0.2"}));
  EXPECT_EQ(fieldUnit("height_above_ground", "ft"), "ft");
  EXPECT_EQ(fieldUnit("intensity", "m"), "");
  const ScalarLegend counts = scalarLegend("m3c2_count1", ColorRamp::Viridis, {0, 1234}, "");
  EXPECT_EQ(counts.title, "m3c2_count1");
  texts.clear();
  for (const auto& tick : counts.ticks) texts.push_back(tick.text);
  // Step 1234 / 6 = 205.7 -> 500; 1000 is kept, 0 and 1234's neighbours are the ends themselves.
  EXPECT_EQ(texts, (std::vector<std::string>{"0", "1234", "500", "1000"}));
}

// --- `parallax render --color m3c2_distance --legend`, end to end ---------------------------

struct Rendered {
  int rc = 0;
  std::string log;
  RgbaImage image;
};

// `render` of the signed scene in kSignedLook.
Rendered renderSigned(const TempDir& dir, const std::string& options) {
  const auto ply = dir.write("signed.ply", signedPly());
  const auto png = dir / "out.png";
  const auto log = dir / "log";
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render '" + ply.string() +
                              "' -o '" + png.string() + "' " + kSignedLook + " " + options +
                              " 2>'" + log.string() + "'";
  Rendered r;
  r.rc = runWithoutLeakCheck(command);
  r.log = readText(log);
  if (r.rc == 0) r.image = readPng(png);
  return r;
}

TEST(RenderLegend, PointsAndTheBarTakeTheDivergingRampOverTheSymmetricPercentileRange) {
  TempDir dir;
  const Rendered r = renderSigned(
      dir, "--color m3c2_distance --color-ramp coolwarm --color-percentiles 10,90 --legend");
  ASSERT_EQ(r.rc, 0) << r.log;
  // Finite values sorted: -0.4 -0.2 -0.1 0 0.05 0.1 0.3 1; ranks round(0.1 * 7) = 1 and
  // round(0.9 * 7) = 6: -0.2 and 0.3, made symmetric: -0.3 .. 0.3.
  const double reach = double(0.3f);
  EXPECT_NE(r.log.find("m3c2_distance from -0.300000012 to 0.300000012"), std::string::npos)
      << r.log;

  expectSignedLegendPicture(r.image, reach);
}

TEST(RenderLegend, NoLegendWithoutTheFlagAndNoneWithoutAScalarAttribute) {
  TempDir dir;
  Rendered r = renderSigned(dir, "--color m3c2_distance --color-ramp coolwarm");
  ASSERT_EQ(r.rc, 0) << r.log;
  for (int y = 0; y < 20; ++y) {
    for (int x = kWidth - 60; x < kWidth; ++x) ASSERT_EQ(pixel(r.image, x, y), kMagenta);
  }
  r = renderSigned(dir, "--legend");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("--legend shows a scalar attribute's ramp"), std::string::npos) << r.log;
  r = renderSigned(dir, "--color m3c2_distance --color-percentiles 50,10");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.log.find("--color-percentiles takes LOW,HIGH"), std::string::npos) << r.log;
}

}  // namespace
}  // namespace parallax::test
