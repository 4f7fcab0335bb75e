// With 1-pixel square points, no lighting and no EDL, every point lights exactly the pixel its
// projection falls in (OpenGL's point rule: the pixel whose centre lies in the point's 1x1
// square). Projected here on the CPU in double and compared pixel for pixel, at UTM coordinates
// seen from a few metres, where a float-only pipeline is off by many pixels.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "render/draw_set.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

struct Pixel {
  int column, row;  // row 0 is the top
  friend auto operator<=>(const Pixel&, const Pixel&) = default;
};

// The pixels the points must light; points within `margin` pixels of a pixel edge are dropped
// from the cloud before rendering, since the GPU's rounding (llvmpipe snaps to 1/256 pixel) may
// put them on either side.
std::set<Pixel> expectedPixels(std::vector<std::array<double, 3>>& world, const Camera& camera,
                               int width, int height, const Bounds3& bounds, double margin) {
  const ClipRange range = camera.clipRange(bounds);
  const glm::dmat4 view = camera.viewMatrix();
  const glm::dmat4 projection = camera.projectionMatrix(double(width) / height, range);
  std::set<Pixel> pixels;
  std::vector<std::array<double, 3>> kept;
  for (const auto& p : world) {
    // The view matrix applied in two steps (rotation of the difference) so that double keeps
    // the precision at UTM coordinates.
    const glm::dvec3 eye = glm::dmat3(view) * (glm::dvec3(p[0], p[1], p[2]) - camera.position);
    const glm::dvec4 clip = projection * glm::dvec4(eye, 1.0);
    const bool visible = clip.w > 0 && std::abs(clip.x) <= clip.w && std::abs(clip.y) <= clip.w &&
                         clip.z >= 0 && clip.z <= clip.w;
    if (!visible) {
      kept.push_back(p);  // must light nothing
      continue;
    }
    const double x = (clip.x / clip.w + 1.0) * 0.5 * width;
    const double y = (clip.y / clip.w + 1.0) * 0.5 * height;
    const double fx = x - std::floor(x), fy = y - std::floor(y);
    if (fx < margin || fx > 1 - margin || fy < margin || fy > 1 - margin) continue;
    kept.push_back(p);
    pixels.insert({int(std::floor(x)), height - 1 - int(std::floor(y))});
  }
  world = kept;
  return pixels;
}

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

void checkExactPixels(std::array<double, 3> origin, double extent, const Camera& camera,
                      std::uint32_t chunk_points, RasterizerKind rasterizer) {
  constexpr int kWidth = 160, kHeight = 120;
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<double, 3>> world;
  for (int i = 0; i < 3000; ++i) {
    world.push_back({origin[0] + extent * unit(random), origin[1] + extent * unit(random),
                     origin[2] + extent * unit(random)});
  }
  // Quantize first (the cloud holds millimetres), then project exactly what the GPU will get.
  const PointCloud quantized = makeCloud(world, origin, 0.001);
  for (std::size_t i = 0; i < world.size(); ++i) {
    world[i] = {quantized.worldX(i), quantized.worldY(i), quantized.worldZ(i)};
  }
  const std::set<Pixel> expected =
      expectedPixels(world, camera, kWidth, kHeight, quantized.bounds, 0.05);
  const PointCloud cloud = makeCloud(world, origin, 0.001);

  RenderSettings settings;
  settings.color = ColorMode::Uniform;
  settings.point_size_px = 1.0f;
  settings.rasterizer = rasterizer;
  PointUploadOptions upload;
  upload.max_chunk_points = chunk_points;
  // The camera's clip range comes from the cloud's bounds, as `parallax render` computes it.
  const RgbaImage image = renderImage(cloud, camera, kWidth, kHeight, settings, upload);
  const std::set<Pixel> lit = litPixels(image);

  ASSERT_GT(expected.size(), 200u) << "the scene should put many points in view";
  std::vector<Pixel> missing, extra;
  std::set_difference(expected.begin(), expected.end(), lit.begin(), lit.end(),
                      std::back_inserter(missing));
  std::set_difference(lit.begin(), lit.end(), expected.begin(), expected.end(),
                      std::back_inserter(extra));
  SCOPED_TRACE(rasterizerKindName(rasterizer));
  EXPECT_TRUE(missing.empty()) << missing.size() << " expected pixels not lit, first at column "
                               << missing[0].column << " row " << missing[0].row;
  EXPECT_TRUE(extra.empty()) << extra.size() << " pixels lit that no point projects to, first at "
                             << "column " << extra[0].column << " row " << extra[0].row;
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelNearTheOrigin) {
  headlessContext();
  Camera camera;
  camera.lookAt({3.0, -4.0, 2.5}, {0.2, 0.1, -0.1}, {0, 0, 1});
  // Both rasterizers: GL_POINTS and the compute rasterizer light the same, exact pixels.
  for (const auto kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
    checkExactPixels({0.0, 0.0, 0.0}, 1.5, camera, 1u << 20, kind);
  }
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelAtUtmCoordinatesFromAFewMetres) {
  headlessContext();
  // An easting of 500 km and a northing of 5 000 km: a float there is good to 0.5 m.
  const std::array<double, 3> origin{512345.678, 5412345.321, 312.5};
  Camera camera;
  camera.lookAt({origin[0] + 2.0, origin[1] - 3.0, origin[2] + 1.5},
                {origin[0] + 0.1, origin[1], origin[2]}, {0, 0, 1});
  // Small chunks, so that the chunk origins differ and every chunk's offset is exercised.
  for (const auto kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
    checkExactPixels(origin, 1.2, camera, 500, kind);
  }
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelInOrthographicProjection) {
  headlessContext();
  const std::array<double, 3> origin{698000.25, 4999000.75, 45.0};
  Camera camera;
  camera.lookAt({origin[0] - 2.0, origin[1] - 2.0, origin[2] + 3.0},
                {origin[0], origin[1], origin[2]}, {0, 0, 1});
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 2.5;
  for (const auto kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
    checkExactPixels(origin, 1.0, camera, 700, kind);
  }
}

TEST(RenderGeometry, PngFirstRowIsTheTopOfTheImage) {
  headlessContext();
  // One point above the view's centre must land in the upper half of the image.
  const PointCloud cloud = makeCloud({{0.01, 0.0, 0.5}, {0.0, 0.0, -100.0}}, {0, 0, 0}, 0.001);
  Camera camera;
  camera.lookAt({0.0, -5.0, 0.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
  RenderSettings settings;
  settings.color = ColorMode::Uniform;
  const RgbaImage image = renderImage(cloud, camera, 64, 64, settings);
  const auto lit = litPixels(image);
  ASSERT_EQ(lit.size(), 1u);
  EXPECT_LT(lit.begin()->row, 32);
  EXPECT_EQ(lit.begin()->column, 32);
}

TEST(RenderGeometry, PickReturnsTheWorldPositionOfThePointUnderThePixel) {
  headlessContext();
  const std::array<double, 3> origin{512345.5, 5412345.25, 300.0};
  const PointCloud cloud = makeCloud(
      {{origin[0], origin[1], origin[2]}, {origin[0] + 0.5, origin[1] + 0.8, origin[2] - 0.3}},
      origin, 0.001);
  Camera camera;
  camera.lookAt({origin[0] - 1.0, origin[1] - 3.0, origin[2] + 1.0},
                {origin[0], origin[1], origin[2]}, {0, 0, 1});
  RenderSettings settings;
  settings.point_size_px = 3.0f;
  GpuPointCloud gpu(cloud);
  Renderer renderer;
  RenderTarget target(64, 64);
  const View view{camera, {0, 0, 64, 64}};
  renderer.render(gpu, std::span(&view, 1), settings, target.framebuffer(), 64, 64);
  // The target is the view's centre: pixel (32, 32) from the bottom left holds it (a 3-pixel
  // point covers 31..33).
  const auto picked = renderer.pick(32, 32);
  ASSERT_TRUE(picked.has_value());
  // Across the view the pick is the pixel's centre, up to half a pixel (3 cm here) from the
  // point; along the view it is the point's depth, to the float depth buffer's precision.
  const glm::dvec3 point(origin[0], origin[1], origin[2]);
  EXPECT_LT(glm::length(*picked - point), 0.05);
  EXPECT_NEAR(glm::dot(*picked - camera.position, camera.forward()),
              glm::dot(point - camera.position, camera.forward()), 1e-3);
  EXPECT_FALSE(renderer.pick(2, 60).has_value()) << "nothing is drawn in that corner";
}

// One white 8-pixel point on black whose centre is a quarter pixel off the pixel grid, so that
// its edges cut pixels; a second point far outside the view only widens the bounds.
RgbaImage renderOffGridPoint(int samples, bool edl, PointShape shape = PointShape::Square) {
  const PointCloud cloud =
      makeCloud({{0.25 / 16, 0.25 / 16, 0.0}, {50.0, 50.0, -1.0}}, {0, 0, 0}, 0.001);
  Camera camera;
  camera.lookAt({0.0, 0.0, 10.0}, {0.0, 0.0, 0.0}, {0, 1, 0});
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 2.0;  // 16 pixels per unit at 32 x 32
  RenderSettings settings;
  settings.color = ColorMode::Uniform;
  settings.point_size_px = 8.0f;
  settings.samples = samples;
  settings.edl = edl;
  settings.shape = shape;
  return renderImage(cloud, camera, 32, 32, settings);
}

struct Coverage {
  int full = 0, partial = 0;
  double area = 0;  // in pixels: the sum of the pixels' grey levels
};

Coverage coverageOf(const RgbaImage& image) {
  Coverage coverage;
  for (std::size_t p = 0; p < image.pixels.size(); p += 4) {
    const int grey = image.pixels[p];
    EXPECT_EQ(grey, image.pixels[p + 1]);
    EXPECT_EQ(grey, image.pixels[p + 2]);
    if (grey == 255) ++coverage.full;
    if (grey > 0 && grey < 255) ++coverage.partial;
    coverage.area += grey / 255.0;
  }
  return coverage;
}

TEST(RenderGeometry, WithoutMultisamplingAPixelIsThePointOrTheBackground) {
  headlessContext();
  const Coverage coverage = coverageOf(renderOffGridPoint(0, false));
  EXPECT_EQ(coverage.partial, 0);
  EXPECT_EQ(coverage.full, 64);
}

TEST(RenderGeometry, MultisamplingBlendsTheEdgesOfAPoint) {
  headlessContext();
  const Coverage coverage = coverageOf(renderOffGridPoint(4, false));
  // The edges cut a row and a column on each side: between 8 + 8 + 1 pixels (grid-aligned
  // coverage on one axis) and 2 x (8 + 8) + 4.
  EXPECT_GE(coverage.partial, 17);
  EXPECT_LE(coverage.partial, 36);
  EXPECT_GE(coverage.full, 49);  // the 7 x 7 inside at least
  // The blend keeps the point's area: 64 pixels, up to the 4-sample quantization of the edges.
  EXPECT_NEAR(coverage.area, 64.0, 4.0);
}

TEST(RenderGeometry, MultisamplingBlendsTheEdgeOfARoundPoint) {
  headlessContext();
  // The disc is cut per fragment: without a shading per sample only the pixels where the disc
  // meets the square's edge would be partial; with it, the whole circle (about 2 pi 4 pixels).
  const Coverage coverage = coverageOf(renderOffGridPoint(4, false, PointShape::Round));
  EXPECT_GE(coverage.partial, 16);
  EXPECT_NEAR(coverage.area, 3.14159 * 16.0, 4.0);
}

TEST(RenderGeometry, EyeDomeLightingOfAMultisampledFlatPointDoesNotDarkenItsInside) {
  headlessContext();
  // One depth everywhere: no pixel has a nearer neighbour, so nothing may be shaded. An edge
  // pixel's resolved eye depth is an average with the empty samples; read as a depth, it would
  // look nearer than the inside and blacken the pixels next to it.
  const Coverage with_edl = coverageOf(renderOffGridPoint(4, true));
  const Coverage without = coverageOf(renderOffGridPoint(4, false));
  EXPECT_EQ(with_edl.full, without.full);
  EXPECT_NEAR(with_edl.area, without.area, 0.5);
}

TEST(PointBuffers, MortonOrderInterleavesXThenYThenZ) {
  const PointCloud cloud =
      makeCloud({{0, 0, 1}, {1, 1, 0}, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}}, {0, 0, 0}, 1.0);
  EXPECT_EQ(mortonOrder(cloud), (std::vector<std::uint32_t>{2, 4, 3, 1, 0, 5}));
}

TEST(PointBuffers, LocalSpacingIsTheMedianGapOfEachBlockOf32FromTheFirstPoint) {
  // Points along a line with gaps that change at every point, some repeated (no gap).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> gap(0.001, 1.0);
  std::vector<glm::dvec3> points;
  double x = 0.0;
  for (int i = 0; i < 100'003; ++i) {
    if (i % 7 != 3) x += gap(random);
    points.push_back({x, 0.5 * x, 2.0});
  }
  std::vector<float> expected(points.size());
  for (std::size_t start = 0; start < points.size(); start += 32) {
    const std::size_t end = std::min(start + 32, points.size());
    std::vector<double> gaps;
    for (std::size_t i = start + 1; i < end; ++i) {
      const double d = glm::length(points[i] - points[i - 1]);
      if (d > 0) gaps.push_back(d);
    }
    std::sort(gaps.begin(), gaps.end());
    for (std::size_t i = start; i < end; ++i) expected[i] = float(gaps[gaps.size() / 2]);
  }
  // The same every run, whatever the threads do (adaptive point sizes come from it).
  for (int run = 0; run < 4; ++run) EXPECT_EQ(localSpacing(points), expected) << "run " << run;
}

TEST(PointBuffers, ChunksHoldAtMostTheirLimitAndEveryPoint) {
  headlessContext();
  std::vector<std::array<double, 3>> world;
  for (int i = 0; i < 2500; ++i) world.push_back({i * 0.01, (i % 50) * 0.02, 0.0});
  const PointCloud cloud = makeCloud(world, {0, 0, 0}, 0.001);
  PointUploadOptions options;
  options.max_chunk_points = 1000;
  const GpuPointCloud gpu(cloud, options);
  ASSERT_EQ(gpu.chunks().size(), 3u);
  EXPECT_EQ(gpu.chunks()[0].count, 1000u);
  EXPECT_EQ(gpu.chunks()[2].count, 500u);
  EXPECT_EQ(gpu.pointCount(), 2500u);
  EXPECT_GE(gpu.gpuBytes(), 2500u * (12 + 4 + 4 + 8));
  Bounds3 all;
  for (const PointChunk& chunk : gpu.chunks()) {
    all.extend(chunk.bounds);
    // The origin is inside the chunk: chunk-relative floats stay small.
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(chunk.origin[a], chunk.bounds.min[a]);
      EXPECT_LE(chunk.origin[a], chunk.bounds.max[a]);
    }
  }
  EXPECT_EQ(all, cloud.bounds);
  // A regular grid 1 cm apart along x and 2 cm along y: the typical spacing is about 1 cm.
  EXPECT_GT(gpu.typicalSpacing(), 0.005);
  EXPECT_LT(gpu.typicalSpacing(), 0.05);
}

TEST(DrawSets, ANodesSpacingSizesItsPointsInAdaptiveMode) {
  headlessContext();
  constexpr int kSize = 101;  // odd: the point's centre is a pixel's centre
  Camera camera;
  camera.lookAt({0.0, -10.0, 0.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
  camera.fov_y_deg = 60.0;
  const PointCloud cloud = makeCloud({{0.0, 0.0, 0.0}}, {0.0, 0.0, 0.0}, 1e-4);
  const GpuPointCloud gpu(cloud);
  RenderSettings settings;
  settings.color = ColorMode::Uniform;
  settings.size_mode = PointSizeMode::Adaptive;
  settings.adaptive_scale = 1.0f;
  Renderer renderer;
  RenderTarget target(kSize, kSize);
  const View view{camera, {0, 0, kSize, kSize}};
  auto litCount = [&](float node_spacing) {
    DrawSet set = gpu.drawSet();
    set.items.at(0).node_spacing = node_spacing;
    renderer.render(set, std::span(&view, 1), settings, target.framebuffer(), kSize, kSize);
    return litPixels({kSize, kSize, target.readRgba()}).size();
  };
  // Pixels per world unit at depth 10: (101 / 2) / tan(30 degrees) / 10. A node spacing of
  // 5 (or 7) pixels' worth gives a 5 x 5 (7 x 7) square.
  const double per_unit = kSize / 2.0 / std::tan(glm::radians(30.0)) / 10.0;
  EXPECT_EQ(litCount(float(5.0 / per_unit)), 25u);
  EXPECT_EQ(litCount(float(7.0 / per_unit)), 49u);
  // Without a node spacing, the chunk's own per-point spacing (none for one point): the fixed
  // size, 1 pixel.
  EXPECT_EQ(litCount(0.0f), 1u);
}

}  // namespace
}  // namespace parallax::test
