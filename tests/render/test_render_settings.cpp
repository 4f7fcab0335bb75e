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

}  // namespace
}  // namespace parallax
