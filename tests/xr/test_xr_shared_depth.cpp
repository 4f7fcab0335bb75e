// A headset's eyes, as view --xr turns them into views (xr/stage_mapping.h), keep the compute
// rasterizer's shared projection of depth (render/compute_rasterizer.cpp, shareDepth): the eyes
// of a real headset have asymmetric fovs that are not mirror images of each other (calibrated
// per eye) and poses that the runtime gives in float. Losing the shared path draws the same
// picture at a higher cost, so only this test would notice.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <random>
#include <vector>

#include "../render/render_test_support.h"
#include "xr/stage_mapping.h"

namespace parallax {
namespace {

using test::headlessContext;
using test::makeCloud;

// What an XrPosef holds: every component rounded to float.
StagePose asXrPose(const glm::dvec3& position, const glm::dquat& orientation) {
  StagePose pose;
  pose.position = glm::dvec3(glm::vec3(position));
  pose.orientation = glm::dquat(glm::quat(orientation));
  return pose;
}

TEST(XrSharedDepth, AHeadsetsEyesShareOneProjectionOfDepth) {
  headlessContext();
  const glm::dvec3 base(512345.25, 5412345.75, 312.5);  // UTM: the file's base centre
  StagePlacement placement;
  placement.origin = base;
  // A head 1.7 m above the floor, turned 30 degrees left and looking 10 degrees down, eyes
  // 63 mm apart along its x, computed in double and then rounded to float, as a runtime's are.
  const glm::dvec3 head(0.4, 1.7, -0.3);
  const glm::dquat turn = glm::angleAxis(glm::radians(30.0), glm::dvec3(0, 1, 0)) *
                          glm::angleAxis(glm::radians(-10.0), glm::dvec3(1, 0, 0));
  // Calibrated eyes: each wider on its outer side, and no two angles mirror images.
  const EyeFov fovs[2] = {{-0.942, 0.698, 0.768, -0.960}, {-0.716, 0.934, 0.777, -0.951}};
  const int eye_width = 96, eye_height = 104;
  std::vector<View> views;
  int rows = 0;
  for (int e = 0; e < 2; ++e) {
    const StagePose pose =
        asXrPose(head + turn * glm::dvec3(e == 0 ? -0.0315 : 0.0315, 0.0, 0.0), turn);
    const EyeView eye = eyeView(placement, fovs[e], pose, e * eye_width, eye_width, eye_height);
    views.push_back(eye.view);
    rows = std::max(rows, eye.view.viewport.height);
  }
  ASSERT_NE(views[0].viewport.height, views[1].viewport.height) << "unequal vertical fovs";

  // Points on the stage 1-4 m in front of the head (stage -z is file +y), below eye height.
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::array<double, 3>> world;
  for (int i = 0; i < 30000; ++i) {
    const glm::dvec3 stage =
        head + turn * glm::dvec3(-1.5 + 3.0 * unit(random), -1.2 + 1.4 * unit(random),
                                 -1.0 - 3.0 * unit(random));
    const glm::dvec3 file = stageToFile(placement, stage);
    world.push_back({file.x, file.y, file.z});
  }
  const PointCloud cloud = makeCloud(world, {base.x, base.y, base.z}, 1e-4);
  GpuPointCloud gpu(cloud);
  RenderSettings settings;
  settings.rasterizer = RasterizerKind::Compute;
  settings.shape = PointShape::Round;
  settings.point_size_px = 3.0f;
  const int width = 2 * eye_width;
  const auto draw = [&](bool share, bool* shared) {
    ComputeRasterizerOptions options;
    options.share_depth = share;
    Renderer renderer(options);
    RenderTarget target(width, rows);
    const FrameStats stats =
        renderer.render(gpu.drawSet(), views, settings, target.framebuffer(), width, rows);
    EXPECT_EQ(stats.rasterizer, RasterizerKind::Compute) << stats.fallback_reason;
    *shared = renderer.computeRasterizer().sharedDepthOfLastFrame();
    return target.readRgba();
  };
  bool shared = false, alone = true;
  const std::vector<std::uint8_t> together = draw(true, &shared);
  const std::vector<std::uint8_t> apart = draw(false, &alone);
  EXPECT_TRUE(shared) << "the headset's eyes were each projected alone";
  EXPECT_FALSE(alone);
  // The float poses put eye 1 a fraction of a micrometre off eye 0's plane: the shared path draws
  // it in that plane, which may move a point across a pixel's edge, rarely.
  std::size_t lit = 0, same = 0;
  for (std::size_t p = 0; p < together.size(); p += 4) {
    const bool lit_together = together[p] | together[p + 1] | together[p + 2];
    const bool lit_apart = apart[p] | apart[p + 1] | apart[p + 2];
    if (!lit_together && !lit_apart) continue;
    ++lit;
    same += std::equal(&together[p], &together[p + 4], &apart[p]);
  }
  EXPECT_GT(lit, std::size_t(width * rows / 4)) << "nearly empty";
  EXPECT_GE(double(same), 0.999 * double(lit)) << same << " of " << lit << " pixels the same";
}

}  // namespace
}  // namespace parallax
