// The placement of the cloud in the stage and the eye views that follow from it (xr/stage_mapping.h).
#include "xr/stage_mapping.h"

#include <gtest/gtest.h>

#include <cmath>

namespace parallax {
namespace {

TEST(StageMapping, FileToStageIsTheIssuesMapping) {
  const StagePlacement p{{500000.0, 5400000.0, 300.0}, 0.5};
  const glm::dvec3 s = fileToStage(p, {500010.0, 5400004.0, 302.0});
  EXPECT_DOUBLE_EQ(s.x, 5.0);   // (X - Ox) * S
  EXPECT_DOUBLE_EQ(s.y, 1.0);   // (Z - Oz) * S: file up is stage up
  EXPECT_DOUBLE_EQ(s.z, -2.0);  // -(Y - Oy) * S: file north is stage forward (-z)
  const glm::dvec3 back = stageToFile(p, s);
  EXPECT_DOUBLE_EQ(back.x, 500010.0);
  EXPECT_DOUBLE_EQ(back.y, 5400004.0);
  EXPECT_DOUBLE_EQ(back.z, 302.0);
}

TEST(StageMapping, DefaultOriginIsTheBaseCentreAndTabletopFitsOneMetre) {
  Bounds3 b;
  b.min = {10.0, 20.0, 5.0};
  b.max = {14.0, 28.0, 7.0};
  const glm::dvec3 o = baseCentre(b);
  EXPECT_EQ(o, glm::dvec3(12.0, 24.0, 5.0));
  const StagePlacement t = tabletopPlacement(b);
  EXPECT_EQ(t.origin, o);
  EXPECT_DOUBLE_EQ(t.scale, 1.0 / 8.0);
}

// The eye view's matrices put a point where the XrFovf's tangents say, for an asymmetric fov and
// a turned eye, with the cloud far from the origin: horizontally exactly, vertically within the
// quarter pixel that the taller viewport's whole rows allow.
TEST(StageMapping, EyeViewProjectsAsTheFovTangentsSay) {
  const StagePlacement p{{500000.0, 5400000.0, 300.0}, 2.0};
  const EyeFov fov{-0.9, 0.5, 0.4, -0.7};
  StagePose eye;
  eye.position = {0.3, 1.6, -0.2};
  eye.orientation = glm::angleAxis(glm::radians(30.0), glm::dvec3(0, 1, 0)) *
                    glm::angleAxis(glm::radians(-10.0), glm::dvec3(1, 0, 0));
  const int width = 300, height = 200;
  const EyeView ev = eyeView(p, fov, eye, 0, width, height);
  EXPECT_LE(ev.row_error, 0.25);
  EXPECT_GE(ev.source_y, 0);
  EXPECT_LE(ev.source_y + height, ev.view.viewport.height);
  for (const glm::dvec3 local :
       {glm::dvec3(0.4, 0.1, -3.0), glm::dvec3(-1.5, -1.0, -2.5), glm::dvec3(0.0, 0.0, -10.0)}) {
    // A point given in eye space, taken to the stage and then to the file.
    const glm::dvec3 file = stageToFile(p, eye.position + eye.orientation * local);
    const ClipRange range{0.01, 100.0};
    const glm::dvec4 clip = ev.view.camera.projectionMatrix(ev.view.aspect(), range) *
                            ev.view.camera.viewMatrix() * glm::dvec4(file, 1.0);
    const double window_x = (clip.x / clip.w + 1) / 2 * width;
    const double window_y = (clip.y / clip.w + 1) / 2 * ev.view.viewport.height - ev.source_y;
    const double tx = local.x / -local.z, ty = local.y / -local.z;
    EXPECT_NEAR(window_x,
                (tx - std::tan(fov.left)) / (std::tan(fov.right) - std::tan(fov.left)) * width,
                1e-6);
    EXPECT_NEAR(window_y,
                (ty - std::tan(fov.down)) / (std::tan(fov.up) - std::tan(fov.down)) * height,
                0.25 + 1e-6);
  }
}

}  // namespace
}  // namespace parallax
