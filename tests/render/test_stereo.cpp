// Stereo rendering on llvmpipe, checked against the CPU:
// - geometry: 1-pixel points placed on the CPU land, in each eye, on the pixel the off-axis
//   formula gives; a point on the convergence plane on the same pixel in both eyes;
// - composition: every display mode's picture equals the composition of the two eyes' pictures
//   rendered alone (halves, rows, colour channels, Dubois' matrices), eye-dome lighting per eye;
// - shared work: a chunk is culled once for both eyes and drawn once per eye that sees it;
// - picking in either eye.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "render/stereo.h"
#include "render/stereo_compositor.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

struct Pixel {
  int column, row;  // row 0 is the top
  friend auto operator<=>(const Pixel&, const Pixel&) = default;
};

std::set<Pixel> litPixels(const RgbaImage& image) {
  std::set<Pixel> pixels;
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) {
      const std::uint8_t* p = &image.pixels[(std::size_t(row) * image.width + column) * 4];
      if (p[0] | p[1] | p[2]) pixels.insert({column, row});
    }
  }
  return pixels;
}

// One stereo frame of `cloud` into a width x height image.
RgbaImage renderStereo(const PointCloud& cloud, const Camera& camera, const StereoSettings& stereo,
                       int width, int height, const RenderSettings& settings,
                       FrameStats* stats = nullptr, const PointUploadOptions& upload = {}) {
  headlessContext();
  GpuPointCloud gpu(cloud, upload);
  Renderer renderer;
  RenderTarget target(width, height);
  const StereoFrame frame = stereoFrame(camera, stereo, width, height);
  const FrameStats result =
      renderer.render(gpu.drawSet(), frame, settings, target.framebuffer(), width, height);
  expectDrawnBy(result, settings.rasterizer);
  if (stats) *stats = result;
  return {width, height, target.readRgba()};
}

// Camera at the origin looking along +y, right +x, up +z: depth is y, across is x and z.
Camera axisCamera() {
  Camera camera;
  camera.lookAt({0.0, 0.0, 0.0}, {0.0, 10.0, 0.0}, {0, 0, 1});
  camera.fov_y_deg = 60.0;
  return camera;
}

constexpr double kSeparation = 0.5, kConvergence = 10.0;

StereoSettings stereoOf(StereoMode mode) {
  StereoSettings stereo;
  stereo.mode = mode;
  stereo.eye_separation = kSeparation;
  stereo.convergence = kConvergence;
  return stereo;
}

// Points at several depths, one row each, and the pixels each eye must light. Each eye's column
// comes from the off-axis formula written out here (not from the renderer's matrices): for an
// eye at offset e along right, NDC x = ((x - e) / d + e / C) / tan_x, tan_x = tan(fov_y / 2) x
// the projection's aspect. Every point is placed so that both eyes' positions are at least 0.15
// pixel from a pixel edge (the GPU snaps to 1/256 pixel).
struct ParallaxScene {
  std::vector<std::array<double, 3>> points;
  std::set<Pixel> left_pixels, right_pixels;  // within each eye's viewport
  std::vector<double> depths;
  std::vector<int> gl_rows;                        // OpenGL rows (from the bottom)
  std::vector<std::pair<double, double>> columns;  // continuous left and right columns
};

ParallaxScene parallaxScene(int viewport_width, int viewport_height, double projection_aspect) {
  const double tan_y = std::tan(60.0 * std::numbers::pi / 360.0), tan_x = tan_y * projection_aspect;
  const double e = kSeparation / 2;
  auto column = [&](double x, double d, double offset) {
    const double ndc = ((x - offset) / d + offset / kConvergence) / tan_x;
    return (ndc + 1.0) / 2.0 * viewport_width;
  };
  auto fine = [](double position) {
    const double f = position - std::floor(position);
    return f > 0.15 && f < 0.85;
  };
  ParallaxScene scene;
  const std::vector<double> depths{4.0, 6.0, 8.5, kConvergence, 13.0, 20.0, 45.0};
  for (std::size_t i = 0; i < depths.size(); ++i) {
    const double d = depths[i];
    // The row: pixel centres, from the bottom, 10 rows apart; z from the vertical projection.
    const int gl_row = 8 + 12 * int(i);
    const double z = (gl_row + 0.5 - viewport_height / 2.0) / (viewport_height / 2.0) * tan_y * d;
    // The left eye near the middle, at a fraction of a pixel that suits both eyes.
    bool placed = false;
    for (double a = 0.2; a < 0.81 && !placed; a += 0.05) {
      const double target = viewport_width / 2 - 6 + a;
      // Solve column(x, d, -e) = target for x.
      const double ndc = target / viewport_width * 2.0 - 1.0;
      const double x = (ndc * tan_x - (-e) / kConvergence) * d + (-e);
      const double left = column(x, d, -e), right = column(x, d, e);
      if (!fine(left) || !fine(right)) continue;
      placed = true;
      scene.points.push_back({x, d, z});
      const int row = viewport_height - 1 - gl_row;
      scene.left_pixels.insert({int(std::floor(left)), row});
      scene.right_pixels.insert({int(std::floor(right)), row});
      scene.depths.push_back(d);
      scene.gl_rows.push_back(gl_row);
      scene.columns.push_back({left, right});
    }
    EXPECT_TRUE(placed) << "no placement for depth " << d;
  }
  return scene;
}

RenderSettings onePixelUniform() {
  RenderSettings settings;
  settings.color = ColorMode::Uniform;
  settings.point_size_px = 1.0f;
  return settings;
}

TEST(StereoGeometry, PointsLandWhereTheOffAxisFormulaPutsThemInBothEyes) {
  constexpr int kWidth = 320, kHeight = 100, kHalf = kWidth / 2;
  const ParallaxScene scene = parallaxScene(kHalf, kHeight, double(kHalf) / kHeight);
  const PointCloud cloud = makeCloud(scene.points, {0.0, 0.0, 0.0}, 1e-6);
  const RgbaImage image = renderStereo(cloud, axisCamera(), stereoOf(StereoMode::SideBySide),
                                       kWidth, kHeight, onePixelUniform());
  std::set<Pixel> expected = scene.left_pixels;
  for (const Pixel& p : scene.right_pixels) expected.insert({p.column + kHalf, p.row});
  EXPECT_EQ(litPixels(image), expected);

  // The formula's parallax, f * s * (1/C - 1/d) pixels (f the focal length in pixels), is what
  // the columns differ by; on the convergence plane it is zero: the same pixel in both eyes.
  const double f = kHeight / (2.0 * std::tan(60.0 * std::numbers::pi / 360.0));
  for (std::size_t i = 0; i < scene.depths.size(); ++i) {
    const double d = scene.depths[i];
    EXPECT_NEAR(scene.columns[i].second - scene.columns[i].first,
                f * kSeparation * (1 / kConvergence - 1 / d), 1e-9);
    if (d == kConvergence) {
      EXPECT_EQ(std::floor(scene.columns[i].first), std::floor(scene.columns[i].second));
    }
  }
  // The scene spans crossed (near) and uncrossed (far) parallax of several pixels.
  EXPECT_LT(scene.columns.front().second - scene.columns.front().first, -3.0);
  EXPECT_GT(scene.columns.back().second - scene.columns.back().first, 1.5);
}

TEST(StereoGeometry, SqueezedSideBySideKeepsTheWholeOutputsAspectInEachHalf) {
  constexpr int kWidth = 320, kHeight = 100, kHalf = kWidth / 2;
  // Each eye is projected at 320:100 into a 160-pixel-wide half.
  const ParallaxScene scene = parallaxScene(kHalf, kHeight, double(kWidth) / kHeight);
  const PointCloud cloud = makeCloud(scene.points, {0.0, 0.0, 0.0}, 1e-6);
  const RgbaImage image =
      renderStereo(cloud, axisCamera(), stereoOf(StereoMode::SideBySideSqueezed), kWidth, kHeight,
                   onePixelUniform());
  std::set<Pixel> expected = scene.left_pixels;
  for (const Pixel& p : scene.right_pixels) expected.insert({p.column + kHalf, p.row});
  EXPECT_EQ(litPixels(image), expected);
}

TEST(StereoGeometry, TopBottomPutsTheLeftEyeOnTop) {
  constexpr int kWidth = 160, kHeight = 200, kHalf = kHeight / 2;
  const ParallaxScene scene = parallaxScene(kWidth, kHalf, double(kWidth) / kHalf);
  const PointCloud cloud = makeCloud(scene.points, {0.0, 0.0, 0.0}, 1e-6);
  const RgbaImage image = renderStereo(cloud, axisCamera(), stereoOf(StereoMode::TopBottom), kWidth,
                                       kHeight, onePixelUniform());
  std::set<Pixel> expected = scene.left_pixels;
  for (const Pixel& p : scene.right_pixels) expected.insert({p.column, p.row + kHalf});
  EXPECT_EQ(litPixels(image), expected);
}

// The wavy sheet seen from the golden images' camera, rendered per eye and in each mode.
struct CompositionCase {
  PointCloud cloud = makeWavySheet(32, {0.0, 0.0, 0.0});
  Camera camera;
  StereoSettings stereo;
  StereoEyes eyes;
  RenderSettings settings;

  explicit CompositionCase(StereoMode mode, bool edl = false) {
    camera.lookAt({1.8, -2.6, 2.2}, {0.0, 0.0, 0.0}, {0, 0, 1});
    camera.fov_y_deg = 45.0;
    stereo.mode = mode;
    stereo.eye_separation = 0.3;  // a strong parallax, so that the eyes' pictures differ a lot
    eyes = stereoEyes(camera, 0.3, autoConvergence(camera), false);
    settings.point_size_px = 2.0f;
    settings.edl = edl;
    settings.background = {0.1f, 0.2f, 0.3f};
  }
  RgbaImage eye(const Camera& eye_camera, int width, int height) const {
    return renderImage(cloud, eye_camera, width, height, settings);
  }
  RgbaImage output(int width, int height) const {
    return renderStereo(cloud, camera, stereo, width, height, settings);
  }
};

const std::uint8_t* at(const RgbaImage& image, int column, int row) {
  return &image.pixels[(std::size_t(row) * image.width + column) * 4];
}

// `expected(column, row, channel)` for every pixel of `image`; at most `tolerance` apart.
template <class Expected>
void expectImage(const RgbaImage& image, Expected expected, int tolerance = 0) {
  int worst = 0, worst_column = 0, worst_row = 0;
  std::size_t lit = 0;
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) {
      for (int c = 0; c < 3; ++c) {
        const int difference = std::abs(int(at(image, column, row)[c]) - expected(column, row, c));
        if (difference > worst) worst = difference, worst_column = column, worst_row = row;
      }
      // Unlike the top-left corner, which is the background in every scene here.
      if (!std::equal(at(image, column, row), at(image, column, row) + 3, at(image, 0, 0))) ++lit;
    }
  }
  EXPECT_LE(worst, tolerance) << "at column " << worst_column << " row " << worst_row;
  EXPECT_GT(lit, std::size_t(image.width * image.height / 20)) << "the picture is nearly empty";
}

TEST(StereoComposition, SideBySideHalvesAreTheEyesPicturesWithEyeDomeLightingPerEye) {
  const CompositionCase scene(StereoMode::SideBySide, true);
  const RgbaImage output = scene.output(192, 96);
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 96);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 96);
  expectImage(output, [&](int column, int row, int c) {
    return column < 96 ? at(left, column, row)[c] : at(right, column - 96, row)[c];
  });
}

TEST(StereoComposition, TopBottomHalvesAreTheEyesPictures) {
  const CompositionCase scene(StereoMode::TopBottom);
  const RgbaImage output = scene.output(96, 192);
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 96);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 96);
  expectImage(output, [&](int column, int row, int c) {
    return row < 96 ? at(left, column, row)[c] : at(right, column, row - 96)[c];
  });
}

TEST(StereoComposition, AnaglyphIsTheLeftEyesRedAndTheRightEyesGreenAndBlue) {
  const CompositionCase scene(StereoMode::Anaglyph, true);
  const RgbaImage output = scene.output(96, 80);
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 80);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 80);
  expectImage(output, [&](int column, int row, int c) {
    return c == 0 ? at(left, column, row)[0] : at(right, column, row)[c];
  });
}

TEST(StereoComposition, DuboisAnaglyphAppliesTheLeastSquaresMatrices) {
  // Dubois' red-cyan matrices as his page publishes them (rows: output r, g, b).
  const double kLeft[3][3] = {
      {0.437, 0.449, 0.164}, {-0.062, -0.062, -0.024}, {-0.048, -0.050, -0.017}};
  const double kRight[3][3] = {
      {-0.011, -0.032, -0.007}, {0.377, 0.761, 0.009}, {-0.026, -0.093, 1.234}};
  const CompositionCase scene(StereoMode::AnaglyphDubois);
  const RgbaImage output = scene.output(96, 80);
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 80);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 80);
  // One step of rounding in 8 bits.
  expectImage(
      output,
      [&](int column, int row, int c) {
        double value = 0.0;
        for (int k = 0; k < 3; ++k) {
          value += kLeft[c][k] * at(left, column, row)[k] / 255.0 +
                   kRight[c][k] * at(right, column, row)[k] / 255.0;
        }
        return int(std::lround(std::clamp(value, 0.0, 1.0) * 255.0));
      },
      1);
}

TEST(StereoComposition, InterlacedTakesEvenRowsFromTheTopFromTheLeftEye) {
  const CompositionCase scene(StereoMode::Interlaced);
  const RgbaImage output = scene.output(96, 81);  // odd: the bottom row is the left eye's
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 81);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 81);
  expectImage(output, [&](int column, int row, int c) {
    return row % 2 == 0 ? at(left, column, row)[c] : at(right, column, row)[c];
  });
}

TEST(StereoComposition, SwappedEyesExchangeThePictures) {
  CompositionCase scene(StereoMode::SideBySide);
  scene.stereo.swap_eyes = true;
  const RgbaImage output = scene.output(192, 96);
  const RgbaImage left = scene.eye(scene.eyes.left, 96, 96);
  const RgbaImage right = scene.eye(scene.eyes.right, 96, 96);
  expectImage(output, [&](int column, int row, int c) {
    return column < 96 ? at(right, column, row)[c] : at(left, column - 96, row)[c];
  });
}

TEST(StereoSharedWork, AChunkIsCulledOnceForBothEyesAndDrawnForEachEyeThatSeesIt) {
  // Three one-point chunks: straight ahead far away (both eyes), just in front of the left eye
  // (left only, see StereoRig.FrustaOfTheEyesSeeTheirOwnSideOfTheScene), behind the camera (none).
  const Camera camera = axisCamera();
  StereoSettings stereo = stereoOf(StereoMode::SideBySide);
  stereo.eye_separation = 2.0;
  stereo.convergence = 8.0;
  const std::vector<std::array<double, 3>> points{
      {0.0, 40.0, 0.0}, {-1.0, 1.0, 0.0}, {0.0, -5.0, 0.0}};
  PointUploadOptions upload;
  upload.max_chunk_points = 1;
  for (const RasterizerKind kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
    RenderSettings settings = onePixelUniform();
    settings.rasterizer = kind;
    FrameStats stats;
    renderStereo(makeCloud(points, {0.0, 0.0, 0.0}, 1e-4), camera, stereo, 200, 100, settings,
                 &stats, upload);
    ASSERT_EQ(stats.rasterizer, kind);
    EXPECT_EQ(stats.chunks_drawn, 2u);
    EXPECT_EQ(stats.chunks_culled, 1u);
    // GL_POINTS: a draw call per chunk and eye that sees it. Compute: one dispatch per chunk,
    // each point read once and projected into both eyes.
    EXPECT_EQ(stats.draw_calls, kind == RasterizerKind::Points ? 3u : 2u);
    EXPECT_EQ(stats.points_drawn, 2u);
  }
}

TEST(StereoPicking, APickInEitherEyeFindsThePointDrawnThere) {
  constexpr int kWidth = 320, kHeight = 100, kHalf = kWidth / 2;
  headlessContext();
  Renderer renderer;
  RenderTarget target(kWidth, kHeight);
  const double f =
      kHeight / (2.0 * std::tan(60.0 * std::numbers::pi / 360.0));  // pixels per unit at depth 1
  // Side by side: both eyes' halves. Anaglyph: the left eye's picture is the one picked.
  for (const StereoMode mode : {StereoMode::SideBySide, StereoMode::Anaglyph}) {
    const bool halves = mode == StereoMode::SideBySide;
    const int eye_width = halves ? kHalf : kWidth;
    const ParallaxScene scene = parallaxScene(eye_width, kHeight, double(eye_width) / kHeight);
    const PointCloud cloud = makeCloud(scene.points, {0.0, 0.0, 0.0}, 1e-6);
    GpuPointCloud gpu(cloud);
    const StereoFrame frame = stereoFrame(axisCamera(), stereoOf(mode), kWidth, kHeight);
    renderer.render(gpu.drawSet(), frame, onePixelUniform(), target.framebuffer(), kWidth, kHeight);
    for (std::size_t k = 0; k < scene.points.size(); ++k) {
      const glm::dvec3 point(scene.points[k][0], scene.points[k][1], scene.points[k][2]);
      // The pick reads the pixel's centre at the point's depth: within a pixel of the point.
      const double tolerance = scene.depths[k] / f;
      std::vector<int> columns{int(std::floor(scene.columns[k].first))};
      if (halves) columns.push_back(kHalf + int(std::floor(scene.columns[k].second)));
      for (const int column : columns) {
        const auto picked = renderer.pick(column, scene.gl_rows[k]);
        ASSERT_TRUE(picked.has_value()) << stereoModeName(mode) << " point " << k;
        EXPECT_LT(glm::length(*picked - point), tolerance)
            << stereoModeName(mode) << " point " << k;
      }
    }
    // Between the points there is nothing to pick.
    EXPECT_FALSE(renderer.pick(3, 3).has_value());
  }
}

}  // namespace
}  // namespace parallax::test
