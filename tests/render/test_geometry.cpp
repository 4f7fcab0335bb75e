// With 1-pixel square points, no lighting and no EDL, every point lights exactly the pixel its
// projection falls in (OpenGL's point rule: the pixel whose centre lies in the point's 1x1
// square). Projected here on the CPU in double and compared pixel for pixel, at UTM coordinates
// seen from a few metres, where a float-only pipeline is off by many pixels.
#include <gtest/gtest.h>

#include <set>

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
                      std::uint32_t chunk_points) {
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
  EXPECT_TRUE(missing.empty()) << missing.size() << " expected pixels not lit, first at column "
                               << missing[0].column << " row " << missing[0].row;
  EXPECT_TRUE(extra.empty()) << extra.size() << " pixels lit that no point projects to, first at "
                             << "column " << extra[0].column << " row " << extra[0].row;
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelNearTheOrigin) {
  headlessContext();
  Camera camera;
  camera.lookAt({3.0, -4.0, 2.5}, {0.2, 0.1, -0.1}, {0, 0, 1});
  checkExactPixels({0.0, 0.0, 0.0}, 1.5, camera, 1u << 20);
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelAtUtmCoordinatesFromAFewMetres) {
  headlessContext();
  // An easting of 500 km and a northing of 5 000 km: a float there is good to 0.5 m.
  const std::array<double, 3> origin{512345.678, 5412345.321, 312.5};
  Camera camera;
  camera.lookAt({origin[0] + 2.0, origin[1] - 3.0, origin[2] + 1.5},
                {origin[0] + 0.1, origin[1], origin[2]}, {0, 0, 1});
  // Small chunks, so that the chunk origins differ and every chunk's offset is exercised.
  checkExactPixels(origin, 1.2, camera, 500);
}

TEST(RenderGeometry, EveryPointLightsExactlyItsPixelInOrthographicProjection) {
  headlessContext();
  const std::array<double, 3> origin{698000.25, 4999000.75, 45.0};
  Camera camera;
  camera.lookAt({origin[0] - 2.0, origin[1] - 2.0, origin[2] + 3.0}, {origin[0], origin[1], origin[2]},
                {0, 0, 1});
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 2.5;
  checkExactPixels(origin, 1.0, camera, 700);
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

}  // namespace
}  // namespace parallax::test
