// The registration preview (registration/cloud_registration.h): ICP through registerClouds
// recovers a known motion of a synthetic surface; the preview cloud puts the target in blue and
// the source, moved by a transform, in orange; `parallax render` of the previews before and after
// shows each colour where the test projects the clouds' points (an orthographic projection worked
// out here). One side of the preview alone, as the viewer's point-pairs picking draws it.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.h"
#include "io/point_file.h"
#include "registration/cloud_registration.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::runWithoutLeakCheck;

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

TEST(RegistrationPreview, TargetBlueThenSourceOrangeMovedByTheTransform) {
  const PointCloud target = wavyPatch(), source = movedPatch();
  const RigidTransform back = kMotion.inverse();
  const PointCloud preview = registrationPreview(source, target, back);
  ASSERT_EQ(preview.count, target.count + source.count);
  for (std::size_t i = 0; i < target.count; ++i) {
    ASSERT_EQ(preview.colors[i], kPreviewTargetColor);
    ASSERT_NEAR(preview.worldX(i), target.worldX(i), 1e-4);
    ASSERT_NEAR(preview.worldZ(i), target.worldZ(i), 1e-4);
  }
  for (std::size_t i = 0; i < source.count; ++i) {
    const std::size_t j = target.count + i;
    ASSERT_EQ(preview.colors[j], kPreviewSourceColor);
    // Moved back: onto the target's point i (the patch's own order).
    ASSERT_NEAR(preview.worldX(j), target.worldX(i), 2e-4);
    ASSERT_NEAR(preview.worldY(j), target.worldY(i), 2e-4);
  }
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

using Rgb = std::array<int, 3>;

// A picture of `cloud` from above, orthographic, centred on its bounds' centre: the view's
// height is the bounds' largest side (as `render --ortho --eye` makes it), over 400 pixels.
struct Picture {
  RgbaImage image;
  double centre_x = 0, centre_y = 0, pixels_per_unit = 1;

  Rgb at(double x, double y) const {
    const int px = int(std::floor(image.width / 2.0 + (x - centre_x) * pixels_per_unit));
    const int py = int(std::floor(image.height / 2.0 - (y - centre_y) * pixels_per_unit));
    if (px < 0 || py < 0 || px >= image.width || py >= image.height) return {-1, -1, -1};
    const std::uint8_t* p = &image.pixels[(std::size_t(py) * image.width + px) * 4];
    return {p[0], p[1], p[2]};
  }
};

Picture renderFromAbove(const TempDir& dir, const PointCloud& cloud, const std::string& name) {
  const auto ply = dir / (name + ".ply");
  writePointFile(cloud, ply);
  const Bounds3& b = cloud.bounds;
  Picture picture;
  picture.centre_x = 0.5 * (b.min[0] + b.max[0]);
  picture.centre_y = 0.5 * (b.min[1] + b.max[1]);
  picture.pixels_per_unit =
      400.0 / std::max({b.max[0] - b.min[0], b.max[1] - b.min[1], b.max[2] - b.min[2]});
  const std::string centre =
      std::to_string(picture.centre_x) + "," + std::to_string(picture.centre_y);
  const auto png = dir / (name + ".png");
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render '" + ply.string() +
                              "' -o '" + png.string() +
                              "' --width 400 --height 400 --point-size 4 --ortho --eye " + centre +
                              ",50 --target " + centre + ",0 --up 0,1,0 --rasterizer points -q";
  EXPECT_EQ(runWithoutLeakCheck(command), 0) << command;
  picture.image = readPng(png);
  return picture;
}

TEST(RegistrationPreview, RenderedBeforeSideBySideAndAfterOnTopOfEachOther) {
  TempDir dir;
  const PointCloud target = wavyPatch(), source = movedPatch();
  const Rgb blue{kPreviewTargetColor.r, kPreviewTargetColor.g, kPreviewTargetColor.b};
  const Rgb orange{kPreviewSourceColor.r, kPreviewSourceColor.g, kPreviewSourceColor.b};

  const PointCloud before = registrationPreview(source, target, RigidTransform{});
  const Picture image_before = renderFromAbove(dir, before, "before");
  const int sampled = int((target.count + 6) / 7);
  int blue_hits = 0, orange_hits = 0;
  for (std::size_t i = 0; i < target.count; i += 7) {
    blue_hits += image_before.at(target.worldX(i), target.worldY(i)) == blue;
    orange_hits += image_before.at(source.worldX(i), source.worldY(i)) == orange;
  }
  EXPECT_EQ(blue_hits, sampled);
  EXPECT_EQ(orange_hits, sampled);

  // After: the source moved onto the target (both colours there); where it was, nothing (the
  // picture is now of the target's extent alone: the source's old place is off it).
  const PointCloud after = registrationPreview(source, target, kMotion.inverse());
  const Picture image_after = renderFromAbove(dir, after, "after");
  int either = 0, orange_after = 0, inside = 0;
  for (std::size_t i = 0; i < target.count; i += 7) {
    const Rgb c = image_after.at(target.worldX(i), target.worldY(i));
    if (c == Rgb{-1, -1, -1}) continue;  // on the picture's right or bottom edge
    ++inside;
    either += c == blue || c == orange;
    orange_after += c == orange;
    if (c != blue && c != orange) ADD_FAILURE() << c[0] << ' ' << c[1] << ' ' << c[2];
  }
  EXPECT_GT(inside, sampled * 3 / 4);  // (the edges: the view is the bounds exactly)
  EXPECT_EQ(either, inside);
  EXPECT_GT(orange_after, 0);  // the source is drawn there, not left behind
  EXPECT_EQ(image_after.at(source.worldX(0), source.worldY(0)), (Rgb{-1, -1, -1}));
}

}  // namespace
}  // namespace parallax::test
