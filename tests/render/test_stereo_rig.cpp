// The stereo rig without OpenGL: eye positions, the off-axis frusta (zero parallax at the
// convergence plane, the parallax formula elsewhere, no vertical parallax), the orthographic
// shear, the automatic defaults, the views of every display mode, and mode names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render/frustum.h"
#include "render/stereo.h"

namespace parallax::test {
namespace {

Camera testCamera() {
  Camera camera;
  camera.lookAt({3.0, -8.0, 4.0}, {0.5, 1.0, 0.0}, {0, 0, 1});
  camera.fov_y_deg = 50.0;
  return camera;
}

// Normalised device coordinates of world point `p` seen by `camera` at `aspect`.
glm::dvec2 ndc(const Camera& camera, const glm::dvec3& p, double aspect) {
  const ClipRange range{0.01, 1000.0};
  const glm::dvec4 clip =
      camera.projectionMatrix(aspect, range) * camera.viewMatrix() * glm::dvec4(p, 1.0);
  return glm::dvec2(clip) / clip.w;
}

// The world point at `depth` along the camera's forward axis, offset (x, y) across it.
glm::dvec3 atDepth(const Camera& camera, double depth, double x, double y) {
  return camera.position + camera.forward() * depth + camera.right() * x + camera.up() * y;
}

TEST(StereoRig, EyesSitAtHalfTheSeparationAlongRightAndLookTheSameWay) {
  const Camera camera = testCamera();
  const StereoEyes eyes = stereoEyes(camera, 0.4, 8.0, false);
  const glm::dvec3 left_offset = eyes.left.position - camera.position;
  const glm::dvec3 right_offset = eyes.right.position - camera.position;
  EXPECT_NEAR(glm::dot(left_offset, camera.right()), -0.2, 1e-12);
  EXPECT_NEAR(glm::dot(right_offset, camera.right()), 0.2, 1e-12);
  EXPECT_NEAR(glm::length(left_offset), 0.2, 1e-12);
  EXPECT_NEAR(glm::length(right_offset), 0.2, 1e-12);
  // Parallel view directions (never toe-in), same up, same pivot and lens.
  EXPECT_EQ(eyes.left.orientation, camera.orientation);
  EXPECT_EQ(eyes.right.orientation, camera.orientation);
  EXPECT_EQ(eyes.left.pivot, camera.pivot);
  EXPECT_EQ(eyes.left.fov_y_deg, camera.fov_y_deg);
  EXPECT_DOUBLE_EQ(eyes.left.off_axis_skew, -0.2 / 8.0);
  EXPECT_DOUBLE_EQ(eyes.right.off_axis_skew, 0.2 / 8.0);
}

TEST(StereoRig, SwapExchangesTheEyes) {
  const Camera camera = testCamera();
  const StereoEyes eyes = stereoEyes(camera, 0.4, 8.0, false);
  const StereoEyes swapped = stereoEyes(camera, 0.4, 8.0, true);
  EXPECT_EQ(swapped.left, eyes.right);
  EXPECT_EQ(swapped.right, eyes.left);
}

TEST(StereoRig, ThePlaneAtTheConvergenceDistanceHasZeroParallax) {
  const Camera camera = testCamera();
  const double convergence = 8.0, aspect = 1.5;
  const StereoEyes eyes = stereoEyes(camera, 0.4, convergence, false);
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {2.5, -1.0}, {-3.0, 2.0}, {4.0, 3.0}}) {
    const glm::dvec3 p = atDepth(camera, convergence, x, y);
    const glm::dvec2 left = ndc(eyes.left, p, aspect), right = ndc(eyes.right, p, aspect);
    EXPECT_NEAR(left.x, right.x, 1e-12) << x << ", " << y;
    EXPECT_NEAR(left.y, right.y, 1e-12) << x << ", " << y;
    // And where the mono camera sees it: the screen plane is the mono picture.
    const glm::dvec2 mono = ndc(camera, p, aspect);
    EXPECT_NEAR(left.x, mono.x, 1e-12);
    EXPECT_NEAR(left.y, mono.y, 1e-12);
  }
}

TEST(StereoRig, ParallaxIsTheOffAxisFormulaAndNeverVertical) {
  const Camera camera = testCamera();
  const double separation = 0.4, convergence = 8.0, aspect = 1.5;
  const int viewport_width = 300, viewport_height = 200;
  const StereoEyes eyes = stereoEyes(camera, separation, convergence, false);
  // Focal length in pixels.
  const double f = viewport_height / (2.0 * std::tan(camera.fov_y_deg * std::numbers::pi / 360.0));
  for (const double depth : {2.0, 5.0, 8.0, 12.0, 50.0, 1000.0}) {
    const glm::dvec3 p = atDepth(camera, depth, 0.3, -0.2);
    const glm::dvec2 left = ndc(eyes.left, p, aspect), right = ndc(eyes.right, p, aspect);
    const double parallax_px = (right.x - left.x) * viewport_width / 2;
    EXPECT_NEAR(parallax_px, f * separation * (1 / convergence - 1 / depth), 1e-9) << depth;
    EXPECT_NEAR(left.y, right.y, 1e-12) << depth;
  }
}

TEST(StereoRig, OrthographicEyesGetParallaxLinearInDepth) {
  Camera camera = testCamera();
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 6.0;
  const double separation = 0.4, convergence = 8.0, aspect = 1.5;
  const int viewport_height = 200;
  const StereoEyes eyes = stereoEyes(camera, separation, convergence, false);
  for (const double depth : {2.0, 8.0, 20.0}) {
    const glm::dvec3 p = atDepth(camera, depth, 1.0, 0.5);
    const glm::dvec2 left = ndc(eyes.left, p, aspect), right = ndc(eyes.right, p, aspect);
    const double parallax_px = (right.x - left.x) * viewport_height * aspect / 2;
    // Pixels per unit are height / ortho_height; the shear moves each eye by offset * (d - C) / C.
    EXPECT_NEAR(parallax_px,
                separation * (depth - convergence) / convergence * viewport_height / 6.0, 1e-9);
    EXPECT_NEAR(left.y, right.y, 1e-12);
  }
}

TEST(StereoRig, MonoProjectionIsUnchangedBySkewZero) {
  const Camera camera = testCamera();
  Camera copy = camera;
  copy.off_axis_skew = 0.0;
  const ClipRange range{0.1, 100.0};
  EXPECT_EQ(camera.projectionMatrix(1.5, range), copy.projectionMatrix(1.5, range));
}

TEST(StereoRig, AutomaticConvergenceIsThePivotDepthAndSeparationAThirtiethOfIt) {
  const Camera camera = testCamera();
  const StereoSettings resolved = resolvedStereo({StereoMode::SideBySide}, camera);
  const double pivot_depth = glm::dot(camera.pivot - camera.position, camera.forward());
  EXPECT_NEAR(resolved.convergence, pivot_depth, 1e-12);
  EXPECT_NEAR(resolved.eye_separation, pivot_depth / 30.0, 1e-12);
  const StereoSettings given = resolvedStereo({StereoMode::SideBySide, 0.25, 3.0, true}, camera);
  EXPECT_EQ(given.eye_separation, 0.25);
  EXPECT_EQ(given.convergence, 3.0);
  EXPECT_TRUE(given.swap_eyes);
}

TEST(StereoRig, FrustaOfTheEyesSeeTheirOwnSideOfTheScene) {
  const Camera camera = testCamera();
  const double convergence = 8.0, aspect = 1.0;
  const StereoEyes eyes = stereoEyes(camera, 2.0, convergence, false);
  const ClipRange range{0.1, 100.0};
  const Frustum left(eyes.left.projectionMatrix(aspect, range) * eyes.left.viewMatrix());
  const Frustum right(eyes.right.projectionMatrix(aspect, range) * eyes.right.viewMatrix());
  auto box = [](const glm::dvec3& p) {
    Bounds3 b;
    b.extend(p.x, p.y, p.z);
    b.extend(p.x + 1e-3, p.y + 1e-3, p.z + 1e-3);
    return b;
  };
  // At depth 1 the mono view is +-0.47 wide; each eye's frustum is that, shifted by its offset
  // (1) less its skew times the depth (1/8): the left eye sees world x in [-1.34, -0.41], the
  // right eye [0.41, 1.34]. Straight in front of each eye is only that eye's.
  const glm::dvec3 before_left = atDepth(camera, 1.0, -1.0, 0.0);
  EXPECT_TRUE(left.intersects(box(before_left)));
  EXPECT_FALSE(right.intersects(box(before_left)));
  const glm::dvec3 before_right = atDepth(camera, 1.0, 1.0, 0.0);
  EXPECT_TRUE(right.intersects(box(before_right)));
  EXPECT_FALSE(left.intersects(box(before_right)));
  // Far away both see the middle.
  const glm::dvec3 far_middle = atDepth(camera, 50.0, 0.0, 0.0);
  EXPECT_TRUE(left.intersects(box(far_middle)));
  EXPECT_TRUE(right.intersects(box(far_middle)));
}

TEST(StereoFrame, MonoIsOneViewOfTheWholeOutput) {
  const Camera camera = testCamera();
  const StereoFrame frame = stereoFrame(camera, {}, 640, 360);
  ASSERT_EQ(frame.views.size(), 1u);
  EXPECT_EQ(frame.views[0].camera, camera);
  EXPECT_EQ(frame.views[0].viewport.width, 640);
  EXPECT_EQ(frame.views[0].viewport.height, 360);
  EXPECT_EQ(frame.composition, Composition::Direct);
}

TEST(StereoFrame, EveryModePlacesTheEyesWhereItsDisplayExpectsThem) {
  const Camera camera = testCamera();
  const int width = 641, height = 361;  // odd: the halves differ by a pixel
  auto frame = [&](StereoMode mode) {
    StereoSettings settings;
    settings.mode = mode;
    settings.eye_separation = 0.4;
    settings.convergence = 8.0;
    return stereoFrame(camera, settings, width, height);
  };
  auto viewport = [](const View& view) {
    const Viewport& v = view.viewport;
    return std::array<int, 4>{v.x, v.y, v.width, v.height};
  };
  const StereoEyes eyes = stereoEyes(camera, 0.4, 8.0, false);

  const StereoFrame sbs = frame(StereoMode::SideBySide);
  ASSERT_EQ(sbs.views.size(), 2u);
  EXPECT_EQ(sbs.composition, Composition::Direct);
  EXPECT_EQ(sbs.views[0].camera, eyes.left);
  EXPECT_EQ(sbs.views[1].camera, eyes.right);
  EXPECT_EQ(viewport(sbs.views[0]), (std::array{0, 0, 320, 361}));
  EXPECT_EQ(viewport(sbs.views[1]), (std::array{320, 0, 321, 361}));
  EXPECT_DOUBLE_EQ(sbs.views[0].aspect(), 320.0 / 361.0);  // each half its own aspect

  const StereoFrame squeezed = frame(StereoMode::SideBySideSqueezed);
  EXPECT_EQ(viewport(squeezed.views[0]), (std::array{0, 0, 320, 361}));
  EXPECT_DOUBLE_EQ(squeezed.views[0].aspect(), 641.0 / 361.0);  // the whole output's aspect
  EXPECT_DOUBLE_EQ(squeezed.views[1].aspect(), 641.0 / 361.0);

  const StereoFrame tb = frame(StereoMode::TopBottom);
  EXPECT_EQ(tb.views[0].camera, eyes.left);
  EXPECT_EQ(viewport(tb.views[0]), (std::array{0, 181, 641, 180}));  // top: OpenGL rows go up
  EXPECT_EQ(viewport(tb.views[1]), (std::array{0, 0, 641, 181}));

  for (const auto& [mode, composition] : {std::pair{StereoMode::Anaglyph, Composition::Anaglyph},
                                          {StereoMode::AnaglyphDubois, Composition::AnaglyphDubois},
                                          {StereoMode::Interlaced, Composition::Interlaced},
                                          {StereoMode::QuadBuffer, Composition::QuadBuffer}}) {
    const StereoFrame composed = frame(mode);
    EXPECT_EQ(composed.composition, composition);
    EXPECT_EQ(viewport(composed.views[0]), (std::array{0, 0, 641, 361}));
    EXPECT_EQ(viewport(composed.views[1]), (std::array{641, 0, 641, 361}));
    EXPECT_EQ(composed.views[1].camera, eyes.right);
  }
}

TEST(StereoModes, NamesRoundTripAndUnknownNamesAreRejected) {
  for (const StereoMode mode : allStereoModes()) {
    EXPECT_EQ(parseStereoMode(stereoModeName(mode)), mode);
  }
  EXPECT_EQ(allStereoModes().size(), 8u);
  EXPECT_EQ(parseStereoMode("anaglyph-dubois"), StereoMode::AnaglyphDubois);
  EXPECT_EQ(parseStereoMode("side-by-side"), std::nullopt);
  EXPECT_EQ(stereoModeNames(),
            "mono|sbs|sbs-squeezed|tb|anaglyph|anaglyph-dubois|interlaced|quad-buffer");
}

}  // namespace
}  // namespace parallax::test
