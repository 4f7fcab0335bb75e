// The registration preview (registration/cloud_registration.h): ICP through registerClouds
// recovers a known motion of a synthetic surface; a side of the preview is the cloud in its order,
// moved, in its colour. The viewer's preview in a window (the after picture, the labels of the
// point pairs): tests/render/test_viewer_panels.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "registration/cloud_registration.h"

namespace parallax::test {
namespace {

// A wavy 40 x 40 patch, 0.25 apart: z = sin(x) cos(0.7 y), enough relief to fix all six
// degrees of freedom.
PointCloud wavyPatch() {
  PointCloud cloud;
  cloud.quantization.scale = {1e-4, 1e-4, 1e-4};
  cloud.count = 40 * 40;
  cloud.positions = Column<Int3>(cloud.count);
  std::size_t i = 0;
  for (int a = 0; a < 40; ++a) {
    for (int b = 0; b < 40; ++b) {
      const double x = a * 0.25, y = b * 0.25, z = std::sin(x) * std::cos(0.7 * y);
      cloud.positions[i++] = {cloud.quantization.toQuantized(0, x),
                              cloud.quantization.toQuantized(1, y),
                              cloud.quantization.toQuantized(2, z)};
    }
  }
  cloud.computeBounds();
  return cloud;
}

// The source: the patch moved 20 units along x and turned 2 degrees about z (about the patch's
// centre), so that before registration the two lie side by side.
const RigidTransform kMotion =
    RigidTransform::translation(20, 0, 0) * RigidTransform::translation(5, 5, 0) *
    RigidTransform::rotation(0, 0, 1, 2.0) * RigidTransform::translation(-5, -5, 0);

PointCloud movedPatch() {
  PointCloud source = wavyPatch();
  transformCloud(source, kMotion);
  return source;
}

TEST(RegistrationPreview, IcpFromAnInitialGuessRecoversTheMotion) {
  const PointCloud target = wavyPatch(), source = movedPatch();
  IcpOptions options;
  options.init = RigidTransform::translation(-20, 0, 0);  // the rough guess a user gives
  options.max_distance = 1.0;
  const IcpResult result = registerClouds(source, target, options, "source", "target");
  const RigidTransform error = result.transform * kMotion;  // the identity when exact
  EXPECT_LT(error.angleDegrees(), 0.01);
  EXPECT_LT(error.translationLength(), 1e-3);
  EXPECT_LT(result.rms, 1e-3);
  EXPECT_GT(result.overlap, 0.9);
  PointCloud two;
  two.count = 2;
  two.positions = Column<Int3>(2);
  EXPECT_THROW(registerClouds(two, target, options, "two.ply", "target"), InputError);
}

// One side alone (the viewer's point-pairs picking draws each apart): the cloud's points in its
// order, moved, all in the colour asked, on a scale no coarser than the cloud's.
TEST(RegistrationPreview, OneSideAloneKeepsItsOrderMovedAndInItsColour) {
  const PointCloud target = wavyPatch(), source = movedPatch();
  const PointCloud side = registrationPreviewSide(source, kMotion.inverse(), kPreviewSourceColor);
  ASSERT_EQ(side.count, source.count);
  EXPECT_FALSE(side.hasNormals());
  EXPECT_LE(side.quantization.scale[0], source.quantization.scale[0]);
  for (std::size_t i = 0; i < source.count; ++i) {
    ASSERT_EQ(side.colors[i], kPreviewSourceColor);
    // Point i moved back onto the target's point i.
    ASSERT_NEAR(side.worldX(i), target.worldX(i), 2e-4) << i;
    ASSERT_NEAR(side.worldY(i), target.worldY(i), 2e-4) << i;
    ASSERT_NEAR(side.worldZ(i), target.worldZ(i), 2e-4) << i;
  }
  const PointCloud unmoved = registrationPreviewSide(target, RigidTransform{}, kPreviewTargetColor);
  ASSERT_EQ(unmoved.count, target.count);
  for (std::size_t i = 0; i < target.count; ++i) {
    ASSERT_EQ(unmoved.colors[i], kPreviewTargetColor);
    ASSERT_NEAR(unmoved.worldX(i), target.worldX(i), 1e-9) << i;
    ASSERT_NEAR(unmoved.worldZ(i), target.worldZ(i), 1e-9) << i;
  }
}

}  // namespace
}  // namespace parallax::test
