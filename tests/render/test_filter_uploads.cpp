// A filter change is uniforms only: on a level-of-detail octree whose nodes are all resident, and
// on a whole uploaded cloud, every filter (classes, returns, intensity, elevation, GPS time, clip
// box, polygon) changes the next frame with no byte uploaded (uploadedPointBytes(), the count of
// every byte given to the GL for points) and no node loaded again, and that frame equals, pixel
// for pixel, the render of the points the CPU filter keeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/point_filter.h"
#include "lod/in_memory_octree.h"
#include "render/lod_scene.h"
#include "render/renderer.h"
#include "render/view_extent.h"
#include "render_test_support.h"

namespace parallax {
namespace {

constexpr int kSize = 128;

// The wavy sheet of 40 000 points with whole intensities, returns (1-3 of 1-3) and GPS times at
// 4e8 s a microsecond apart per point.
PointCloud attributedSheet() {
  PointCloud sheet = test::makeWavySheet(200, {500000.0, 4000000.0, 100.0});
  const std::size_t n = sheet.count;
  ScalarColumn r{.name = "return_number", .type = ScalarType::UInt8, .data = ByteBuffer(n)};
  ScalarColumn count{.name = "number_of_returns", .type = ScalarType::UInt8, .data = ByteBuffer(n)};
  ScalarColumn gps{.name = "gps_time", .type = ScalarType::Float64, .data = ByteBuffer(n * 8)};
  for (std::size_t i = 0; i < n; ++i) {
    sheet.intensity[i] = std::round(sheet.intensity[i]);
    const int returns = 1 + int(i % 3);
    count.as<std::uint8_t>()[i] = std::uint8_t(returns);
    r.as<std::uint8_t>()[i] = std::uint8_t(1 + (i / 3) % std::size_t(returns));
    gps.as<double>()[i] = 400000000.0 + double((i * 7919) % n) * 1e-6;
  }
  sheet.scalars.push_back(std::move(r));
  sheet.scalars.push_back(std::move(count));
  sheet.scalars.push_back(std::move(gps));
  return sheet;
}

// One filter of each kind; each keeps part of the sheet.
std::vector<std::pair<std::string, PointFilter>> filters() {
  std::vector<std::pair<std::string, PointFilter>> list;
  PointFilter f;
  f.keepOnlyClasses({0, 1, 2, 5});
  list.emplace_back("classes", f);
  f = {};
  f.keepOnlyReturns({ReturnKind::Last}, {});
  list.emplace_back("returns last", f);
  f = {};
  f.intensity = ValueRange{300.0, 700.0};
  list.emplace_back("intensity", f);
  f = {};
  f.elevation = ValueRange{99.9, 100.1};
  list.emplace_back("elevation", f);
  f = {};
  f.gps_time = ValueRange{400000000.0100005, 400000000.0300005};
  list.emplace_back("gps time", f);
  f = {};
  Bounds3 box;
  box.extend(499999.5, 3999999.2, 0.0);
  box.extend(500000.6, 4000000.7, 200.0);
  f.setClipBox(box, true);
  list.emplace_back("clip box outside", f);
  f = {};
  f.polygon = {{499999.1, 3999999.1},
               {500000.9, 3999999.5},
               {500000.1, 4000000.1},
               {500000.7, 4000000.9},
               {499999.3, 4000000.6}};
  list.emplace_back("polygon", f);
  return list;
}

std::vector<std::uint8_t> renderOf(Renderer& renderer, const DrawSet& draw_set, const View& view,
                                   const RenderSettings& settings) {
  RenderTarget target(kSize, kSize);
  test::expectDrawnBy(
      renderer.render(draw_set, std::span(&view, 1), settings, target.framebuffer(), kSize, kSize),
      settings.rasterizer);
  return target.readRgba();
}

std::size_t differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.size(); i += 4) count += !std::equal(&a[i], &a[i] + 4, &b[i]);
  return count;
}

class FilterUploads : public ::testing::TestWithParam<RasterizerKind> {
 protected:
  void SetUp() override {
    test::headlessContext();
    sheet_ = attributedSheet();
    view_.viewport = {0, 0, kSize, kSize};
    view_.camera = defaultCameraFor(sheet_.bounds, 1.0);
    settings_.rasterizer = GetParam();
  }
  // The CPU-filtered render of every filter, uploaded before the frames under test.
  std::vector<std::vector<std::uint8_t>> expectedPictures(Renderer& renderer) {
    std::vector<std::vector<std::uint8_t>> pictures;
    for (const auto& [name, filter] : filters()) {
      const PointCloud kept = filterPoints(sheet_, filter);
      EXPECT_GT(kept.count, 1000u) << name;
      EXPECT_LT(kept.count, sheet_.count) << name;
      GpuPointCloud gpu(kept);
      pictures.push_back(renderOf(renderer, gpu.drawSet(), view_, settings_));
    }
    return pictures;
  }

  PointCloud sheet_;
  View view_;
  RenderSettings settings_;  // fixed 1-pixel points, RGB
};

TEST_P(FilterUploads, AnOctreeFrameChangesWithNoUploadAndNoLoad) {
  OctreeBuildOptions options;
  options.max_node_points = 2000;
  options.spacing = 0.1;
  const std::unique_ptr<InMemoryOctree> octree = buildOctree(sheet_, options);
  ASSERT_GT(octree->nodes().size(), 9u);
  LodFrameSettings everything;
  everything.selection.point_budget = std::numeric_limits<std::uint64_t>::max();
  everything.selection.min_node_size_px = 0.0;
  LodScene scene(*octree);
  Renderer renderer;
  scene.finishLoading(std::span(&view_, 1), everything);
  ASSERT_TRUE(scene.complete());
  ASSERT_TRUE(scene.drawSet().has_gps_time);
  const auto expected = expectedPictures(renderer);
  const auto plain =
      renderOf(renderer, scene.update(std::span(&view_, 1), everything), view_, settings_);

  const std::uint64_t uploaded = uploadedPointBytes();
  ASSERT_GE(uploaded, sheet_.count * 20) << "the counter missed the nodes' uploads";
  const auto list = filters();
  for (std::size_t i = 0; i < list.size(); ++i) {
    settings_.filter = list[i].second;
    const DrawSet& draw_set = scene.update(std::span(&view_, 1), everything);
    const auto picture = renderOf(renderer, draw_set, view_, settings_);
    EXPECT_EQ(uploadedPointBytes(), uploaded) << list[i].first;
    EXPECT_EQ(scene.stats().uploaded_nodes, 0u) << list[i].first;
    EXPECT_GT(differing(picture, plain), 100u) << list[i].first << ": the filter changed nothing";
    EXPECT_EQ(differing(picture, expected[i]), 0u) << list[i].first;
  }
}

TEST_P(FilterUploads, AWholeCloudFrameChangesWithNoUpload) {
  Renderer renderer;
  const auto expected = expectedPictures(renderer);
  GpuPointCloud gpu(sheet_);
  const auto plain = renderOf(renderer, gpu.drawSet(), view_, settings_);
  const std::uint64_t uploaded = uploadedPointBytes();
  const auto list = filters();
  for (std::size_t i = 0; i < list.size(); ++i) {
    settings_.filter = list[i].second;
    const auto picture = renderOf(renderer, gpu.drawSet(), view_, settings_);
    EXPECT_EQ(uploadedPointBytes(), uploaded) << list[i].first;
    EXPECT_GT(differing(picture, plain), 100u) << list[i].first;
    EXPECT_EQ(differing(picture, expected[i]), 0u) << list[i].first;
  }
}

INSTANTIATE_TEST_SUITE_P(BothRasterizers, FilterUploads,
                         ::testing::Values(RasterizerKind::Points, RasterizerKind::Compute),
                         [](const auto& param_info) {
                           return param_info.param == RasterizerKind::Points
                                      ? std::string("points")
                                      : std::string("compute");
                         });

}  // namespace
}  // namespace parallax
