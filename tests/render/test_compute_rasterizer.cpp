// The compute rasterizer against GL_POINTS on the same scenes (llvmpipe, headless):
// - 1-pixel points: the same pixels lit and the same colours (agreement >= 0.99; the rest are
//   pixels where two points' depths tie within float rounding) in every colour mode, with
//   lighting, eye-dome lighting, orthographic projection and every stereo mode;
// - splats of 2-255 pixels, square and round, light exactly GL_POINTS' pixels, those over
//   kInlineSplatPx through the large splats' list (which grows, or gives way to inline drawing
//   past one binding, with the same picture);
// - only multisampling and an oversized canvas leave a frame to GL_POINTS;
// - picking names the exact point, in either eye;
// - bound ranges, progressive parts, the point filter and exact ties give the same picture.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>

#include "render/stereo.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

// A dense box of random points (overdraw of 10-20 per lit pixel at 128 x 128), every attribute
// set, in chunks of 5000 so that several chunks and batches are drawn.
PointCloud denseCloud(std::size_t count = 60000) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<double, 3>> world;
  for (std::size_t i = 0; i < count; ++i) {
    world.push_back({unit(random), unit(random), 0.5 * unit(random)});
  }
  PointCloud cloud = makeCloud(world, {0.0, 0.0, 0.0}, 1e-5);
  for (std::size_t i = 0; i < count; ++i) {
    const double length = std::sqrt(world[i][0] * world[i][0] + 1.0);
    cloud.normals[i] = {float(world[i][0] / length), 0.0f, float(1.0 / length)};
  }
  return cloud;
}

Camera boxCamera() {
  Camera camera;
  camera.lookAt({1.6, -2.4, 1.8}, {0.0, 0.0, 0.0}, {0, 0, 1});
  camera.fov_y_deg = 50.0;
  return camera;
}

PointUploadOptions smallChunks() {
  PointUploadOptions upload;
  upload.max_chunk_points = 5000;
  return upload;
}

struct Drawn {
  RgbaImage image;
  FrameStats stats;
  std::uint64_t large_splats = 0;  // drawn a workgroup each (compute)
};

Drawn draw(const PointCloud& cloud, const Camera& camera, int width, int height,
           RenderSettings settings, RasterizerKind kind, const StereoSettings& stereo = {},
           const PointUploadOptions& upload = smallChunks()) {
  headlessContext();
  settings.rasterizer = kind;
  GpuPointCloud gpu(cloud, upload);
  Renderer renderer;
  RenderTarget target(width, height);
  Drawn drawn;
  drawn.stats = renderer.render(gpu.drawSet(), stereoFrame(camera, stereo, width, height), settings,
                                target.framebuffer(), width, height);
  drawn.image = {width, height, target.readRgba()};
  if (drawn.stats.rasterizer == RasterizerKind::Compute) {
    drawn.large_splats = renderer.computeRasterizer().largeSplatsOfLastFrame();
  }
  return drawn;
}

struct Agreement {
  std::size_t lit = 0;       // pixels lit (not background) in either picture
  std::size_t same_lit = 0;  // lit in both
  std::size_t same = 0;      // lit in either, all channels within the tolerance
  double litAgreement() const { return lit ? double(same_lit) / lit : 0.0; }
  double colorAgreement() const { return lit ? double(same) / lit : 0.0; }
};

Agreement compare(const RgbaImage& a, const RgbaImage& b, std::array<float, 3> background,
                  int tolerance) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  Agreement agreement;
  const auto is_lit = [&](const std::uint8_t* p) {
    for (int c = 0; c < 3; ++c) {
      if (std::abs(p[c] - int(std::lround(background[c] * 255))) > 0) return true;
    }
    return false;
  };
  for (std::size_t p = 0; p < a.pixels.size(); p += 4) {
    const bool lit_a = is_lit(&a.pixels[p]), lit_b = is_lit(&b.pixels[p]);
    if (!lit_a && !lit_b) continue;
    ++agreement.lit;
    if (lit_a && lit_b) ++agreement.same_lit;
    int worst = 0;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(a.pixels[p + c] - b.pixels[p + c]));
    if (worst <= tolerance) ++agreement.same;
  }
  return agreement;
}

// Compute and GL_POINTS, each as asked for, on one scene: >= 0.99 agreement.
void expectAgreement(const std::string& name, const RenderSettings& settings,
                     const Camera& camera = boxCamera(), const StereoSettings& stereo = {},
                     int width = 128, int height = 128) {
  const PointCloud cloud = denseCloud();
  const Drawn points = draw(cloud, camera, width, height, settings, RasterizerKind::Points, stereo);
  const Drawn compute =
      draw(cloud, camera, width, height, settings, RasterizerKind::Compute, stereo);
  ASSERT_EQ(points.stats.rasterizer, RasterizerKind::Points) << name;
  ASSERT_EQ(compute.stats.rasterizer, RasterizerKind::Compute)
      << name << ": " << compute.stats.fallback_reason;
  // Eye-dome lighting darkens a pixel by its neighbours' depths: one differing pixel changes a
  // few around it by a shade. Colours round the same way in both, so elsewhere they are equal.
  const int tolerance = settings.edl ? 8 : 1;
  const Agreement agreement = compare(points.image, compute.image, settings.background, tolerance);
  EXPECT_GT(agreement.lit, std::size_t(width * height / 5)) << name << ": nearly empty";
  EXPECT_GE(agreement.litAgreement(), 0.99)
      << name << ": " << agreement.same_lit << " of " << agreement.lit << " lit pixels lit by both";
  EXPECT_GE(agreement.colorAgreement(), 0.99)
      << name << ": " << agreement.same << " of " << agreement.lit << " pixels of the same colour";
}

RenderSettings onePixel(ColorMode color) {
  RenderSettings settings;
  settings.color = color;
  return settings;
}

TEST(ComputeVsPoints, OnePixelPointsInEveryColourMode) {
  for (const ColorMode color : {ColorMode::Rgb, ColorMode::Elevation, ColorMode::Intensity,
                                ColorMode::Normal, ColorMode::Classification, ColorMode::Uniform}) {
    expectAgreement(std::string(colorModeName(color)), onePixel(color));
  }
}

TEST(ComputeVsPoints, LightingEyeDomeLightingAndOrthographic) {
  RenderSettings lit = onePixel(ColorMode::Uniform);
  lit.lighting = true;
  expectAgreement("lighting", lit);
  RenderSettings edl = onePixel(ColorMode::Rgb);
  edl.edl = true;
  edl.background = {0.1f, 0.2f, 0.3f};
  expectAgreement("edl", edl);
  Camera ortho = boxCamera();
  ortho.projection = Projection::Orthographic;
  ortho.ortho_height = 2.5;
  RenderSettings lit_ortho = lit;
  expectAgreement("orthographic lighting", lit_ortho, ortho);
  // A 1-pixel disc lights its pixel only where its centre is within half a pixel of the pixel's.
  RenderSettings round = onePixel(ColorMode::Rgb);
  round.shape = PointShape::Round;
  expectAgreement("1-pixel round", round);
}

TEST(ComputeVsPoints, EveryStereoMode) {
  for (const StereoMode mode : allStereoModes()) {
    if (mode == StereoMode::Mono || mode == StereoMode::QuadBuffer) continue;  // no window
    StereoSettings stereo;
    stereo.mode = mode;
    stereo.eye_separation = 0.2;
    RenderSettings settings = onePixel(ColorMode::Rgb);
    settings.edl = mode == StereoMode::AnaglyphDubois;  // EDL per eye before the composition
    const int width =
        mode == StereoMode::SideBySide || mode == StereoMode::SideBySideSqueezed ? 256 : 128;
    const int height = mode == StereoMode::TopBottom ? 256 : 128;
    expectAgreement(std::string(stereoModeName(mode)), settings, boxCamera(), stereo, width,
                    height);
  }
  // Orthographic eyes: the second eye's clip x is the first's plus a shift linear in depth (the
  // compute rasterizer derives it rather than projecting twice), as GL_POINTS projects it.
  StereoSettings stereo;
  stereo.mode = StereoMode::SideBySide;
  stereo.eye_separation = 0.2;
  Camera ortho = boxCamera();
  ortho.projection = Projection::Orthographic;
  ortho.ortho_height = 2.5;
  expectAgreement("orthographic side by side", onePixel(ColorMode::Rgb), ortho, stereo, 256, 128);
}

// Points at positions off the pixel grid, isolated up to 27 pixels: every splat size and shape
// lights exactly the pixels GL_POINTS lights (one uniform colour: where larger splats overlap, at
// equal depth, either may win), up to the GL's largest point, which both clamp to.
TEST(ComputeVsPoints, SplatsLightTheSamePixelsAsSquareAndRoundPoints) {
  std::vector<std::array<double, 3>> world;
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 6; ++i) {
      world.push_back({-0.85 + 0.34 * i + 0.0137 * j, -0.85 + 0.34 * j + 0.0071 * i, 0.0});
    }
  }
  const PointCloud cloud = makeCloud(world, {0, 0, 0}, 1e-6);
  Camera camera;
  camera.lookAt({0.0, 0.0, 10.0}, {0.0, 0.0, 0.0}, {0, 1, 0});
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 2.0;
  for (const PointShape shape : {PointShape::Square, PointShape::Round}) {
    for (const float size :
         {2.0f, 3.0f, 4.5f, 5.0f, 6.0f, 7.0f, 8.0f, 9.0f, 12.5f, 17.0f, 26.0f, 40.0f, 300.0f}) {
      RenderSettings settings = onePixel(ColorMode::Uniform);
      settings.point_size_px = size;
      settings.shape = shape;
      const Drawn points = draw(cloud, camera, 160, 160, settings, RasterizerKind::Points);
      const Drawn compute = draw(cloud, camera, 160, 160, settings, RasterizerKind::Compute);
      ASSERT_EQ(compute.stats.rasterizer, RasterizerKind::Compute);
      EXPECT_EQ(compute.large_splats, size > ComputeRasterizer::kInlineSplatPx ? world.size() : 0u)
          << size << " px";
      const Agreement agreement = compare(points.image, compute.image, settings.background, 0);
      // Squares are exact. A disc's edge may pass through a pixel centre: the two compute
      // gl_PointCoord differently, so such a pixel may go either way (one seen at 7 px), and a
      // large disc's edge crosses more pixel centres.
      const std::size_t allowed =
          shape == PointShape::Square ? 0u : std::size_t(2 + 36 * std::min(size, 40.0f) / 20);
      EXPECT_LE(agreement.lit - agreement.same, allowed)
          << pointShapeName(shape) << " " << size << " px: " << agreement.lit - agreement.same
          << " of " << agreement.lit << " pixels differ";
      EXPECT_GE(agreement.lit,
                std::min<std::size_t>(std::size_t(36 * size * size * 0.7), 160 * 160 / 2))
          << "splats too small";
    }
  }
}

TEST(ComputeVsPoints, AdaptiveAndAttenuatedSizesOfAnySizeAreSplats) {
  // Two clusters of 10 000 points, one near the camera (points of 10+ pixels: listed as large
  // splats), one far (1-2 pixels: drawn inline), in chunks of 5000, overlapping at random depths.
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(-0.2, 0.2);
  std::vector<std::array<double, 3>> world;
  for (const double y : {0.0, 5.0}) {
    for (int i = 0; i < 10000; ++i) world.push_back({unit(random), y + unit(random), unit(random)});
  }
  const PointCloud cloud = makeCloud(world, {0, 0, 0}, 1e-5);
  Camera camera;
  camera.lookAt({0.1, -0.7, 0.15}, {0.0, 2.5, 0.0}, {0, 0, 1});
  for (const PointSizeMode mode : {PointSizeMode::Adaptive, PointSizeMode::Attenuated}) {
    for (const PointShape shape : {PointShape::Square, PointShape::Round}) {
      RenderSettings settings = onePixel(ColorMode::Rgb);
      settings.size_mode = mode;
      settings.shape = shape;
      settings.adaptive_scale = 3.0f;
      settings.world_size = 0.05f;
      settings.max_size_px = 255.0f;
      settings.lighting = true;
      const std::string name =
          std::string(pointSizeModeName(mode)) + " " + std::string(pointShapeName(shape));
      const Drawn points = draw(cloud, camera, 128, 128, settings, RasterizerKind::Points);
      const Drawn compute = draw(cloud, camera, 128, 128, settings, RasterizerKind::Compute);
      ASSERT_EQ(compute.stats.rasterizer, RasterizerKind::Compute) << name;
      EXPECT_EQ(compute.stats.chunks_drawn, 4u) << name;
      EXPECT_GT(compute.large_splats, 1000u) << name;
      EXPECT_LT(compute.large_splats, 10000u) << name << ": the far points are inline";
      const Agreement agreement = compare(points.image, compute.image, settings.background, 1);
      EXPECT_GE(agreement.colorAgreement(), 0.99)
          << name << ": " << agreement.same << " of " << agreement.lit << " pixels agree";
    }
  }
}

// A frame's ranges are grouped so that the large splats a group lists fit the list, which is
// drawn and emptied after each group. With the smallest list (16 384 splats, chunks of 5000
// points: two groups in mono, one chunk a group in stereo) the picture is exactly the one a list of a
// million gives (ties are broken the same way and HQ's sums are integers), and GL_POINTS' where
// it draws the look; in mono and in both eyes of side by side, with splats up to 14 pixels (an
// invocation's loops stay within llvmpipe's limit in stereo: points of 11 pixels and more drawn
// inline were dropped).
TEST(ComputeRasterizer, LargeSplatsAreListedAndDrawnInGroupsWithTheSamePicture) {
  const PointCloud cloud = denseCloud(20000);
  RenderSettings plain = onePixel(ColorMode::Rgb);
  plain.point_size_px = 9.5f;
  RenderSettings hq = plain;
  hq.hq = true;
  RenderSettings round_lit = plain;
  round_lit.point_size_px = 14.0f;
  round_lit.shape = PointShape::Round;
  round_lit.lighting = true;
  StereoSettings sbs;
  sbs.mode = StereoMode::SideBySide;
  sbs.eye_separation = 0.1;
  const std::vector<std::tuple<std::string, RenderSettings, StereoSettings, int>> looks = {
      {"9.5 px squares", plain, {}, 128},
      {"HQ", hq, {}, 128},
      {"14 px round lit, side by side", round_lit, sbs, 256},
      {"HQ side by side", hq, sbs, 256}};
  headlessContext();
  for (const auto& [name, look, stereo, width] : looks) {
    std::optional<RgbaImage> whole_list;
    std::uint64_t listed = 0;
    for (const std::uint32_t per_group : {1u << 20, 1u}) {  // 1: the smallest list
      ComputeRasterizerOptions options;
      options.large_splats_per_group = per_group;
      Renderer renderer(options);
      GpuPointCloud gpu(cloud, smallChunks());
      RenderTarget target(width, 128);
      RenderSettings settings = look;
      settings.rasterizer = RasterizerKind::Compute;
      const FrameStats stats =
          renderer.render(gpu.drawSet(), stereoFrame(boxCamera(), stereo, width, 128), settings,
                          target.framebuffer(), width, 128);
      ASSERT_EQ(stats.rasterizer, RasterizerKind::Compute) << name;
      const RgbaImage image{width, 128, target.readRgba()};
      const std::uint64_t large = renderer.computeRasterizer().largeSplatsOfLastFrame();
      if (!whole_list) {
        // Every point in view (all but a few at the box's corners) is a large splat, once in
        // each eye that sees it.
        EXPECT_GT(large, (cloud.count - 200) * (stereo.mode == StereoMode::Mono ? 1 : 2)) << name;
        whole_list = image;
        listed = large;
        continue;
      }
      EXPECT_EQ(large, listed) << name;
      std::size_t differing = 0;
      for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
        differing += !std::equal(&image.pixels[i], &image.pixels[i] + 4, &whole_list->pixels[i]);
      }
      EXPECT_EQ(differing, 0u) << name;
    }
    if (look.hq) continue;  // GL_POINTS does not blend
    const Drawn points = draw(cloud, boxCamera(), width, 128, look, RasterizerKind::Points, stereo);
    const Agreement agreement = compare(points.image, *whole_list, look.background, 1);
    EXPECT_GE(agreement.colorAgreement(), 0.99)
        << name << ": " << agreement.same << " of " << agreement.lit;
  }
}

// An invocation walks 256 points; llvmpipe stops all its loops after 65 535 iterations in all.
// Inline splats are kept narrow enough for every view count the rasterizer draws.
TEST(ComputeRasterizer, InlineSplatsStayWithinLlvmpipesLoopLimitForEveryViewCount) {
  for (std::size_t views = 1; views <= ComputeRasterizer::kMaxViews; ++views) {
    const float n = std::ceil(ComputeRasterizer::inlineSplatPx(views));
    EXPECT_LE(256.0f * ((n + n * n) * float(views) + float(views) + 1.0f), 65535.0f) << views;
    EXPECT_GE(n, 7.0f) << views;
  }
  EXPECT_EQ(ComputeRasterizer::inlineSplatPx(1), ComputeRasterizer::kInlineSplatPx);
  EXPECT_EQ(ComputeRasterizer::inlineSplatPx(2), ComputeRasterizer::kInlineSplatPx);
}

TEST(ComputeRasterizer, AutoChoosesComputeAndFallsBackWhereItCannotDraw) {
  const PointCloud cloud = denseCloud(2000);
  RenderSettings settings;
  EXPECT_EQ(draw(cloud, boxCamera(), 64, 64, settings, RasterizerKind::Auto).stats.rasterizer,
            RasterizerKind::Compute);
  RenderSettings msaa = settings;
  msaa.samples = 4;
  for (const RasterizerKind kind : {RasterizerKind::Auto, RasterizerKind::Compute}) {
    const FrameStats stats = draw(cloud, boxCamera(), 64, 64, msaa, kind).stats;
    EXPECT_EQ(stats.rasterizer, RasterizerKind::Points);
    EXPECT_NE(stats.fallback_reason.find("multisampling"), std::string::npos);
  }
  // Any point size: splats, up to the GL's largest point.
  for (const float size : {12.0f, 255.0f}) {
    RenderSettings large = settings;
    large.point_size_px = size;
    const Drawn large_drawn = draw(cloud, boxCamera(), 64, 64, large, RasterizerKind::Auto);
    EXPECT_EQ(large_drawn.stats.rasterizer, RasterizerKind::Compute)
        << large_drawn.stats.fallback_reason;
    EXPECT_GT(large_drawn.large_splats, 0u);
  }
  RenderSettings hq_points = settings;
  hq_points.hq = true;
  const FrameStats hq_stats =
      draw(cloud, boxCamera(), 64, 64, hq_points, RasterizerKind::Points).stats;
  EXPECT_EQ(hq_stats.rasterizer, RasterizerKind::Points);
  EXPECT_NE(hq_stats.fallback_reason.find("--hq"), std::string::npos);
  // A canvas beyond one binding of the visibility buffer.
  headlessContext();
  ComputeRasterizerOptions options;
  options.max_range_bytes = 64 * 64 * 4 - 4;
  ComputeRasterizer compute(options);
  EXPECT_FALSE(compute.unsupported(settings, 64, 64).empty());
  EXPECT_TRUE(compute.unsupported(settings, 64, 63).empty());
}

TEST(ComputeRasterizer, PickingNamesTheFrontMostPointInEitherEye) {
  headlessContext();
  // Two points on one line of sight, the nearer one second in the draw order, and a third alone.
  const std::array<double, 3> origin{512345.5, 5412345.25, 300.0};
  const PointCloud cloud = makeCloud({{origin[0], origin[1] + 5.0, origin[2]},
                                      {origin[0], origin[1] + 2.0, origin[2]},
                                      {origin[0] + 0.4, origin[1] + 3.0, origin[2] + 0.2}},
                                     origin, 0.001);
  Camera camera;
  camera.lookAt({origin[0], origin[1] - 1.0, origin[2]}, {origin[0], origin[1], origin[2]},
                {0, 0, 1});
  GpuPointCloud gpu(cloud);
  Renderer renderer;
  RenderTarget target(128, 64);
  StereoSettings stereo;
  stereo.mode = StereoMode::SideBySide;
  stereo.eye_separation = 0.05;
  RenderSettings settings;
  settings.rasterizer = RasterizerKind::Compute;
  settings.point_size_px = 3.0f;
  const StereoFrame frame = stereoFrame(camera, stereo, 128, 64);
  const DrawSet set = gpu.drawSet();
  ASSERT_EQ(renderer.render(set, frame, settings, target.framebuffer(), 128, 64).rasterizer,
            RasterizerKind::Compute);
  // Where each point lands in each eye, from the eye's own matrices.
  int found = 0;
  for (std::size_t v = 0; v < 2; ++v) {
    const View& view = frame.views[v];
    const ClipRange range = view.camera.clipRange(set.bounds);
    const glm::dmat4 to_clip =
        view.camera.projectionMatrix(view.aspect(), range) * view.camera.viewMatrix();
    for (const std::size_t k : {std::size_t(1), std::size_t(2)}) {
      const glm::dvec3 world(cloud.worldX(k), cloud.worldY(k), cloud.worldZ(k));
      const glm::dvec4 clip = to_clip * glm::dvec4(world, 1.0);
      const int x = view.viewport.x + int((clip.x / clip.w + 1) / 2 * view.viewport.width);
      const int y = view.viewport.y + int((clip.y / clip.w + 1) / 2 * view.viewport.height);
      const auto picked = renderer.pickPoint(x, y);
      ASSERT_TRUE(picked.has_value()) << "eye " << v << " point " << k;
      ASSERT_TRUE(picked->point.has_value()) << "compute names the point";
      EXPECT_EQ(picked->view, int(v));
      // Morton order may reorder the points: the chunk's float position names the point.
      EXPECT_LT(glm::length(picked->position - world), 1e-6) << "eye " << v << " point " << k;
      ++found;
    }
  }
  EXPECT_EQ(found, 4);
  EXPECT_FALSE(renderer.pickPoint(1, 1).has_value());
}

// Two eyes as a headset gives them: parallel, 64 mm apart, each frustum asymmetric with its own
// angles (unequal widths and heights, as a calibrated headset's are, so neither is the other's
// mirror image), a rolled head, at UTM coordinates, in viewports of unequal heights.
std::vector<View> headsetEyes(const glm::dvec3& centre) {
  Camera head;
  head.lookAt(centre + glm::dvec3(1.2, -1.9, 1.1), centre, {0, 0, 1});
  head.orientation = head.orientation * glm::angleAxis(0.2, glm::dvec3(0, 0, 1));  // roll
  const struct {
    double side, skew, fov_y_deg, aspect;
    Viewport viewport;
  } eyes[2] = {{-0.032, 0.13, 56.0, 0.92, {0, 0, 96, 112}},
               {0.032, -0.09, 52.0, 0.97, {96, 4, 96, 104}}};
  std::vector<View> views;
  for (const auto& eye : eyes) {
    View view;
    view.camera = head;
    view.camera.position = head.position + head.right() * eye.side;
    view.camera.off_axis_skew = eye.skew;
    view.camera.fov_y_deg = eye.fov_y_deg;
    view.projection_aspect = eye.aspect;
    view.viewport = eye.viewport;
    views.push_back(view);
  }
  return views;
}

// The headset's eyes share one projection of depth (SHARED_DEPTH) and each eye's picture is
// exactly what the eye projected alone gives (share_depth off), pixel for pixel, with splats of
// several sizes too; turned apart by a milliradian, the eyes are projected each alone.
TEST(ComputeRasterizer, AHeadsetsAsymmetricEyesShareTheirDepthAndDrawWhatEachDrawsAlone) {
  headlessContext();
  const glm::dvec3 centre(512345.5, 5412345.25, 300.0);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<double, 3>> world;
  for (int i = 0; i < 40000; ++i) {
    world.push_back(
        {centre.x + unit(random), centre.y + unit(random), centre.z + 0.5 * unit(random)});
  }
  const PointCloud cloud = makeCloud(world, {centre.x, centre.y, centre.z}, 1e-4);
  GpuPointCloud gpu(cloud, smallChunks());
  const std::vector<View> views = headsetEyes(centre);
  const int width = 192, height = 112;
  // One renderer each way, so that each compiles its programs once.
  ComputeRasterizerOptions alone_options;
  alone_options.share_depth = false;
  Renderer sharing, projecting_alone(alone_options);
  RenderTarget target(width, height);
  const auto drawn = [&](const std::vector<View>& eyes, RenderSettings settings, bool share,
                         bool* shared) {
    Renderer& renderer = share ? sharing : projecting_alone;
    settings.rasterizer = RasterizerKind::Compute;
    const FrameStats stats =
        renderer.render(gpu.drawSet(), eyes, settings, target.framebuffer(), width, height);
    EXPECT_EQ(stats.rasterizer, RasterizerKind::Compute) << stats.fallback_reason;
    *shared = renderer.computeRasterizer().sharedDepthOfLastFrame();
    return RgbaImage{width, height, target.readRgba()};
  };
  RenderSettings round_splats;
  round_splats.shape = PointShape::Round;
  round_splats.size_mode = PointSizeMode::Attenuated;
  round_splats.world_size = 0.02f;
  round_splats.lighting = true;
  for (const RenderSettings& settings : {onePixel(ColorMode::Rgb), round_splats}) {
    bool shared = false, alone = true;
    const RgbaImage together = drawn(views, settings, true, &shared);
    const RgbaImage apart = drawn(views, settings, false, &alone);
    EXPECT_TRUE(shared) << "a headset's eyes lost the shared projection";
    EXPECT_FALSE(alone);
    // Tolerance 0: every lit pixel the same colour in both.
    const Agreement agreement = compare(together, apart, settings.background, 0);
    EXPECT_GT(agreement.lit, std::size_t(width * height / 4)) << "nearly empty";
    EXPECT_EQ(agreement.same, agreement.lit);
  }
  // Eyes not parallel (a milliradian of toe-in): each projected alone, and still drawn.
  std::vector<View> toed = views;
  toed[1].camera.orientation =
      toed[1].camera.orientation * glm::angleAxis(1e-3, glm::dvec3(0, 1, 0));
  bool shared = true;
  drawn(toed, onePixel(ColorMode::Rgb), true, &shared);
  EXPECT_FALSE(shared);
}

TEST(ComputeRasterizer, RangesPartsAndTiesGiveTheSamePicture) {
  headlessContext();
  const PointCloud cloud = denseCloud(30000);
  PointUploadOptions one_chunk;
  one_chunk.max_chunk_points = 1u << 20;
  GpuPointCloud gpu(cloud, one_chunk);
  const DrawSet set = gpu.drawSet();
  const View view{boxCamera(), {0, 0, 96, 96}};
  RenderSettings settings;
  settings.rasterizer = RasterizerKind::Compute;
  auto render = [&](Renderer& renderer, const FramePart& part = {}) {
    RenderTarget target(96, 96);
    renderer.render(set, std::span(&view, 1), settings, target.framebuffer(), 96, 96,
                    Composition::Direct, part);
    return target.readRgba();
  };
  Renderer whole;
  const auto reference = render(whole);
  // Ranges of two batches: llvmpipe's 128 MiB binding limit, scaled down.
  ComputeRasterizerOptions options;
  options.max_range_bytes = 2 * kBatchPoints * 12;
  Renderer ranged(options);
  EXPECT_EQ(render(ranged), reference);
  // The same frame again: exact ties are broken the same way every time.
  EXPECT_EQ(render(whole), reference);
  // Progressive: half the chunks of a many-chunk set, then the rest on top.
  GpuPointCloud many(cloud, smallChunks());
  const DrawSet many_set = many.drawSet();
  ASSERT_GE(many_set.items.size(), 4u);
  for (const RasterizerKind kind : {RasterizerKind::Compute, RasterizerKind::Points}) {
    settings.rasterizer = kind;
    Renderer renderer;
    RenderTarget full(96, 96), parts(96, 96);
    renderer.render(many_set, std::span(&view, 1), settings, full.framebuffer(), 96, 96);
    const std::size_t half = many_set.items.size() / 2;
    renderer.render(many_set, std::span(&view, 1), settings, parts.framebuffer(), 96, 96,
                    Composition::Direct, {0, half, false});
    renderer.render(many_set, std::span(&view, 1), settings, parts.framebuffer(), 96, 96,
                    Composition::Direct, {half, many_set.items.size(), true});
    EXPECT_EQ(parts.readRgba(), full.readRgba()) << rasterizerKindName(kind);
  }
}

TEST(ComputeRasterizer, DuplicatePointsShowOneDeterministicColour) {
  // Ten points at one position with ten colours: an exact depth tie in one pixel.
  std::vector<std::array<double, 3>> world(10, {0.1, 0.2, 0.3});
  const PointCloud cloud = makeCloud(world, {0, 0, 0}, 1e-4);
  Camera camera;
  camera.lookAt({0.1, -3.0, 0.3}, {0.1, 0.2, 0.3}, {0, 0, 1});
  RenderSettings settings = onePixel(ColorMode::Rgb);
  const RgbaImage first = draw(cloud, camera, 33, 33, settings, RasterizerKind::Compute).image;
  for (int run = 0; run < 3; ++run) {
    EXPECT_EQ(draw(cloud, camera, 33, 33, settings, RasterizerKind::Compute).image.pixels,
              first.pixels);
  }
  // The tie's colour is one of the points' colours (the smallest packed one).
  const std::uint8_t* centre = &first.pixels[(16 * 33 + 16) * 4];
  bool one_of_them = false;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    one_of_them |= cloud.colors[i].r == centre[0] && cloud.colors[i].g == centre[1] &&
                   cloud.colors[i].b == centre[2];
  }
  EXPECT_TRUE(one_of_them);
}

TEST(ComputeVsPoints, TheFilterDropsTheSamePoints) {
  headlessContext();
  const PointCloud cloud = denseCloud(30000);
  RenderSettings settings = onePixel(ColorMode::Classification);
  // Keep class 5 only (makeCloud: class = index % 19), and x >= 0.2 (a plane).
  settings.filter.classes.fill(0u);
  settings.filter.classes[0] = 1u << 5;
  settings.filter.clip_planes.push_back({1.0, 0.0, 0.0, -0.2});
  const Drawn points = draw(cloud, boxCamera(), 128, 128, settings, RasterizerKind::Points);
  const Drawn compute = draw(cloud, boxCamera(), 128, 128, settings, RasterizerKind::Compute);
  const Agreement agreement = compare(points.image, compute.image, settings.background, 1);
  EXPECT_GE(agreement.colorAgreement(), 0.99);
  EXPECT_GT(agreement.lit, 200u);
  // Every pixel drawn names a point that passes the filter.
  std::set<std::array<double, 3>> kept;
  for (std::size_t i = 5; i < cloud.count; i += 19) {
    kept.insert({cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)});
  }
  GpuPointCloud gpu(cloud, smallChunks());
  Renderer renderer;
  RenderTarget target(128, 128);
  settings.rasterizer = RasterizerKind::Compute;
  const View view{boxCamera(), {0, 0, 128, 128}};
  renderer.render(gpu.drawSet(), std::span(&view, 1), settings, target.framebuffer(), 128, 128);
  std::size_t picked_count = 0;
  for (int y = 0; y < 128; y += 2) {
    for (int x = 0; x < 128; x += 2) {
      const auto picked = renderer.pickPoint(x, y);
      if (!picked) continue;
      ++picked_count;
      EXPECT_GE(picked->position.x, 0.2 - 1e-6);
      const auto nearest = kept.lower_bound({picked->position.x - 1e-6, -10.0, -10.0});
      ASSERT_NE(nearest, kept.end());
      EXPECT_NEAR((*nearest)[0], picked->position.x, 1e-6);
      EXPECT_NEAR((*nearest)[1], picked->position.y, 1e-6);
    }
  }
  EXPECT_GT(picked_count, 50u);
}

TEST(ComputeRasterizer, HighQualityBlendsThePointsWithinTheDepthRange) {
  // On one line of sight: red at depth 10, blue 0.5 % behind it, green 5 % behind. HQ blends red
  // and blue (within 1 %) and leaves green out; without HQ the front-most (red) shows alone.
  std::vector<std::array<double, 3>> world{{0.0, 10.0, 0.0}, {0.0, 10.05, 0.0}, {0.0, 10.5, 0.0}};
  PointCloud cloud = makeCloud(world, {0, 0, 0}, 1e-4);
  cloud.colors[0] = {255, 0, 0, 255};
  cloud.colors[1] = {0, 0, 255, 255};
  cloud.colors[2] = {0, 255, 0, 255};
  Camera camera;
  camera.lookAt({0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0, 0, 1});
  RenderSettings settings = onePixel(ColorMode::Rgb);
  settings.point_size_px = 3.0f;
  const auto centre = [](const RgbaImage& image) {
    const std::uint8_t* p = &image.pixels[(16 * 33 + 16) * 4];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  EXPECT_EQ(centre(draw(cloud, camera, 33, 33, settings, RasterizerKind::Compute).image),
            (std::array<int, 3>{255, 0, 0}));
  settings.hq = true;
  const Drawn hq = draw(cloud, camera, 33, 33, settings, RasterizerKind::Compute);
  ASSERT_EQ(hq.stats.rasterizer, RasterizerKind::Compute);
  EXPECT_EQ(centre(hq.image), (std::array<int, 3>{128, 0, 128}));  // (255 + 0) / 2, rounded
}

}  // namespace
}  // namespace parallax::test
