// Golden images: a small scene rendered headless on llvmpipe in every point-size mode, colour
// mode, with lighting, with eye-dome lighting, with multisampling and in three stereo modes,
// compared with PNGs in tests/render/golden/. Each picture is drawn by both rasterizers (GL_POINTS
// and compute) and both must match the one golden image; multisampling is GL_POINTS' only, and
// the high-quality (--hq) blend the compute rasterizer's only.
//
// A pixel differs when a channel is off by more than kChannelTolerance; an image passes with at
// most kDifferingFraction of its pixels differing (room for another Mesa version's rounding,
// none for a changed picture). The golden files are only rewritten by an explicit command:
//   scripts/regenerate-golden.sh   (runs this test with PARALLAX_REGENERATE_GOLDEN=1; every
//                                   test it runs then fails, having compared nothing)
// A failing test writes what it rendered beside the test's temporary folder and names it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "render/stereo.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

constexpr int kSize = 96;
constexpr int kChannelTolerance = 16;
constexpr double kDifferingFraction = 0.01;

bool regenerating() {
  const char* env = std::getenv("PARALLAX_REGENERATE_GOLDEN");
  return env && std::string(env) == "1";
}

Camera sceneCamera() {
  Camera camera;
  camera.lookAt({1.8, -2.6, 2.2}, {0.0, 0.0, 0.0}, {0, 0, 1});
  camera.fov_y_deg = 45.0;
  return camera;
}

// Stereo: each eye kSize pixels high; side by side is two eyes wide.
RgbaImage renderStereoImage(const PointCloud& cloud, const Camera& camera,
                            const StereoSettings& stereo, const RenderSettings& settings) {
  const int width = stereo.mode == StereoMode::SideBySide ? 2 * kSize : kSize;
  GpuPointCloud gpu(cloud);
  Renderer renderer;
  RenderTarget target(width, kSize);
  expectDrawnBy(renderer.render(gpu.drawSet(), stereoFrame(camera, stereo, width, kSize), settings,
                                target.framebuffer(), width, kSize),
                settings.rasterizer);
  return {width, kSize, target.readRgba()};
}

void checkGoldenWith(const std::string& name, const RenderSettings& settings, const Camera& camera,
                     const StereoSettings& stereo, int sheet_side) {
  headlessContext();
  SCOPED_TRACE(std::string(rasterizerKindName(settings.rasterizer)) + " rasterizer");
  const PointCloud cloud = makeWavySheet(sheet_side, {0.0, 0.0, 0.0});
  const RgbaImage image = stereo.mode == StereoMode::Mono
                              ? renderImage(cloud, camera, kSize, kSize, settings)
                              : renderStereoImage(cloud, camera, stereo, settings);
  const int pixel_count = image.width * image.height;
  const std::filesystem::path golden = std::filesystem::path(PARALLAX_GOLDEN_DIR) / (name + ".png");
  if (regenerating()) {
    // Writing is not checking: a run that rewrites the images fails, so that the variable left
    // set (in a shell, a CI job) can never turn the golden tests into passes.
    writePng(golden, image);
    ADD_FAILURE() << "regenerated " << golden.string()
                  << " (PARALLAX_REGENERATE_GOLDEN=1): compared with nothing; review the image "
                     "and run the test again without the variable";
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(golden))
      << golden << " is missing: run scripts/regenerate-golden.sh and review the images";
  const RgbaImage expected = readPng(golden);
  ASSERT_EQ(expected.width, image.width);
  ASSERT_EQ(expected.height, image.height);
  std::size_t differing = 0;
  int largest = 0;
  for (std::size_t p = 0; p < image.pixels.size(); p += 4) {
    int worst = 0;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(image.pixels[p + c] - expected.pixels[p + c]));
    largest = std::max(largest, worst);
    if (worst > kChannelTolerance) ++differing;
  }
  const std::size_t allowed = std::size_t(kDifferingFraction * pixel_count);
  if (differing > allowed) {
    const std::filesystem::path actual =
        std::filesystem::path(PARALLAX_TEST_TMP) / (name + ".actual.png");
    std::filesystem::create_directories(actual.parent_path());
    writePng(actual, image);
    ADD_FAILURE() << name << ": " << differing << " pixels differ (allowed " << allowed
                  << ", largest channel difference " << largest << "); rendered image: " << actual
                  << "; golden: " << golden;
  }
  // The picture must show something: a blank image would match a blank golden.
  std::size_t lit = 0;
  for (std::size_t p = 0; p < image.pixels.size(); p += 4) {
    if (image.pixels[p] | image.pixels[p + 1] | image.pixels[p + 2]) ++lit;
  }
  EXPECT_GT(lit, std::size_t(pixel_count / 10)) << name << " is nearly empty";
}

// The golden images were drawn by GL_POINTS (and the --hq ones by compute); regeneration uses
// that rasterizer, and the check runs every rasterizer that draws the settings.
void checkGolden(const std::string& name, RenderSettings settings,
                 const Camera& camera = sceneCamera(), const StereoSettings& stereo = {},
                 int sheet_side = 32) {
  const bool points_only = settings.samples > 1, compute_only = settings.hq;
  for (const RasterizerKind kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
    if ((kind == RasterizerKind::Compute && points_only) ||
        (kind == RasterizerKind::Points && compute_only)) {
      continue;
    }
    if (regenerating() && kind == RasterizerKind::Compute && !compute_only) continue;
    settings.rasterizer = kind;
    checkGoldenWith(name, settings, camera, stereo, sheet_side);
  }
}

RenderSettings base() {
  RenderSettings settings;
  settings.point_size_px = 2.0f;
  return settings;
}

// The same size as SizeFixedRound, so that the two differ only in the shape (the base settings'
// 2-pixel squares are ColorRgb's picture already).
TEST(RenderGolden, SizeFixedSquare) {
  RenderSettings settings = base();
  settings.point_size_px = 4.0f;
  checkGolden("size_fixed_square", settings);
}

TEST(RenderGolden, SizeFixedRound) {
  RenderSettings settings = base();
  settings.point_size_px = 4.0f;
  settings.shape = PointShape::Round;
  checkGolden("size_fixed_round", settings);
}

TEST(RenderGolden, SizeAttenuated) {
  RenderSettings settings = base();
  settings.size_mode = PointSizeMode::Attenuated;
  settings.world_size = 0.035f;
  checkGolden("size_attenuated", settings);
}

TEST(RenderGolden, SizeAdaptive) {
  RenderSettings settings = base();
  settings.size_mode = PointSizeMode::Adaptive;
  settings.adaptive_scale = 1.2f;
  checkGolden("size_adaptive", settings);
}

TEST(RenderGolden, ColorRgb) {
  checkGolden("color_rgb", base());
}

TEST(RenderGolden, ColorElevation) {
  RenderSettings settings = base();
  settings.color = ColorMode::Elevation;
  checkGolden("color_elevation", settings);
}

TEST(RenderGolden, ColorIntensity) {
  RenderSettings settings = base();
  settings.color = ColorMode::Intensity;
  checkGolden("color_intensity", settings);
}

TEST(RenderGolden, ColorNormal) {
  RenderSettings settings = base();
  settings.color = ColorMode::Normal;
  checkGolden("color_normal", settings);
}

TEST(RenderGolden, ColorClassification) {
  RenderSettings settings = base();
  settings.color = ColorMode::Classification;
  checkGolden("color_classification", settings);
}

TEST(RenderGolden, ColorUniformOnBackground) {
  RenderSettings settings = base();
  settings.color = ColorMode::Uniform;
  settings.uniform_color = {1.0f, 0.5f, 0.0f};
  settings.background = {0.1f, 0.2f, 0.4f};
  checkGolden("color_uniform", settings);
}

TEST(RenderGolden, Lighting) {
  RenderSettings settings = base();
  settings.color = ColorMode::Uniform;
  settings.lighting = true;
  checkGolden("lighting", settings);
}

TEST(RenderGolden, EyeDomeLighting) {
  RenderSettings settings = base();
  settings.color = ColorMode::Uniform;
  settings.edl = true;
  settings.edl_strength = 1.0f;
  settings.edl_radius_px = 1.4f;
  checkGolden("edl", settings);
}

TEST(RenderGolden, Multisampling) {
  RenderSettings settings = base();
  settings.point_size_px = 4.0f;
  settings.shape = PointShape::Round;
  settings.samples = 4;
  checkGolden("msaa", settings);
}

TEST(RenderGolden, Orthographic) {
  Camera camera = sceneCamera();
  camera.projection = Projection::Orthographic;
  camera.fitToBounds(makeWavySheet(4, {0, 0, 0}).bounds, 1.0);
  checkGolden("orthographic", base(), camera);
}

// Two tests with the same picture test one thing twice: no two golden images may be equal.
TEST(RenderGolden, EveryGoldenImageIsItsOwnPicture) {
  std::vector<std::pair<std::string, RgbaImage>> images;
  for (const auto& entry : std::filesystem::directory_iterator(PARALLAX_GOLDEN_DIR)) {
    if (entry.path().extension() == ".png") {
      images.emplace_back(entry.path().filename().string(), readPng(entry.path()));
    }
  }
  ASSERT_GE(images.size(), 17u);
  for (std::size_t a = 0; a < images.size(); ++a) {
    for (std::size_t b = a + 1; b < images.size(); ++b) {
      EXPECT_FALSE(images[a].second.width == images[b].second.width &&
                   images[a].second.height == images[b].second.height &&
                   images[a].second.pixels == images[b].second.pixels)
          << images[a].first << " and " << images[b].first << " are the same picture";
    }
  }
}

StereoSettings stereo(StereoMode mode) {
  StereoSettings settings;
  settings.mode = mode;
  settings.eye_separation = 0.25;  // more than the automatic 1/30, so that the eyes differ
  return settings;
}

TEST(RenderGolden, StereoSideBySide) {
  checkGolden("stereo_sbs", base(), sceneCamera(), stereo(StereoMode::SideBySide));
}

TEST(RenderGolden, StereoAnaglyphDuboisWithEyeDomeLighting) {
  RenderSettings settings = base();
  settings.edl = true;
  checkGolden("stereo_anaglyph_dubois", settings, sceneCamera(),
              stereo(StereoMode::AnaglyphDubois));
}

TEST(RenderGolden, StereoInterlaced) {
  checkGolden("stereo_interlaced", base(), sceneCamera(), stereo(StereoMode::Interlaced));
}

// High quality: each pixel blends every point within 1 % of the front-most depth. 1-pixel points
// of a dense sheet (160 x 160), several to a pixel.
TEST(RenderGolden, HighQualityBlend) {
  RenderSettings settings = base();
  settings.point_size_px = 1.0f;
  settings.hq = true;
  const Camera camera = sceneCamera();
  checkGolden("hq_blend", settings, camera, {}, 160);
}

TEST(RenderGolden, HighQualitySplatsInStereo) {
  RenderSettings settings = base();
  settings.point_size_px = 3.0f;
  settings.shape = PointShape::Round;
  settings.hq = true;
  settings.edl = true;
  checkGolden("hq_splats_sbs", settings, sceneCamera(), stereo(StereoMode::SideBySide));
}

}  // namespace
}  // namespace parallax::test
