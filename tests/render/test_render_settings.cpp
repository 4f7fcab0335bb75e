// The viewer's look (render_settings.h viewerLook), decided once for `parallax view` and
// `parallax bench render --look viewer`: what it chooses, and what it leaves to the options.
#include <gtest/gtest.h>

#include "render/render_settings.h"

namespace parallax {
namespace {

RenderSettings asked() {
  RenderSettings settings;  // render's defaults: fixed 1-pixel squares, unlit
  settings.point_size_px = 3.0f;
  return settings;
}

TEST(ViewerLook, ChoosesRoundAdaptiveLitPointsForACloudWithSpacingAndNormals) {
  const RenderSettings look = viewerLook(asked(), asked(), {.size = true, .lighting = true},
                                         {.spacing_known = true, .has_normals = true});
  EXPECT_EQ(look.size_mode, PointSizeMode::Adaptive);
  EXPECT_EQ(look.shape, PointShape::Round);
  EXPECT_TRUE(look.lighting);
  EXPECT_EQ(look.point_size_px, 3.0f);  // untouched
}

TEST(ViewerLook, WithoutASpacingKeepsTheAskedSizeAndWithoutNormalsIsUnlit) {
  RenderSettings shown = asked();
  shown.size_mode = PointSizeMode::Adaptive;  // the previous cloud's choice
  shown.shape = PointShape::Round;
  shown.lighting = true;
  const RenderSettings look =
      viewerLook(shown, asked(), {.size = true, .lighting = true}, {.spacing_known = false});
  EXPECT_EQ(look.size_mode, PointSizeMode::Fixed);
  EXPECT_EQ(look.shape, PointShape::Square);
  EXPECT_FALSE(look.lighting);
}

TEST(ViewerLook, LeavesWhatTheOptionsGave) {
  RenderSettings options = asked();
  options.lighting = false;
  const RenderSettings look = viewerLook(options, options, {.size = false, .lighting = false},
                                         {.spacing_known = true, .has_normals = true});
  EXPECT_EQ(look, options);
}

// What a picture needs read (LAZ and COPC decode only those layers): positions always, then
// what the colour mode, the lighting and the filter use; each name once.
TEST(AttributesDrawn, ColourModesAskForWhatTheyShow) {
  RenderSettings settings;
  settings.color = ColorMode::Rgb;
  EXPECT_EQ(attributesDrawn(settings).names(), std::vector<std::string>{"red"});
  settings.color = ColorMode::Intensity;
  EXPECT_EQ(attributesDrawn(settings).names(), std::vector<std::string>{"intensity"});
  settings.color = ColorMode::Classification;
  EXPECT_EQ(attributesDrawn(settings).names(), std::vector<std::string>{"classification"});
  settings.color = ColorMode::Normal;
  EXPECT_EQ(attributesDrawn(settings).names(), (std::vector<std::string>{"nx", "ny", "nz"}));
  for (const ColorMode mode : {ColorMode::Elevation, ColorMode::Uniform}) {
    settings.color = mode;
    const AttributeSelection selection = attributesDrawn(settings);
    EXPECT_FALSE(selection.all());
    EXPECT_TRUE(selection.names().empty()) << colorModeName(mode);
    EXPECT_TRUE(selection.wants("z"));
    EXPECT_FALSE(selection.wants("red"));
  }
}

TEST(AttributesDrawn, LightingScalarsAndFiltersAddTheirsOnce) {
  RenderSettings settings;
  settings.color = ColorMode::Intensity;
  settings.lighting = true;
  settings.scalar.field = "distance";
  settings.filter.keepOnlyClasses({2});
  settings.filter.intensity = ValueRange{0, 100};
  settings.filter.gps_time = ValueRange{1, 2};
  settings.filter.keepOnlyReturns({ReturnKind::First}, {});
  EXPECT_EQ(attributesDrawn(settings).names(),
            (std::vector<std::string>{"distance", "intensity", "nx", "ny", "nz", "classification",
                                      "return_number", "number_of_returns", "gps_time"}));
  settings.color = ColorMode::Normal;  // its normals are the lighting's
  settings.filter = {};
  settings.scalar = {};
  EXPECT_EQ(attributesDrawn(settings).names(), (std::vector<std::string>{"nx", "ny", "nz"}));
}

}  // namespace
}  // namespace parallax
