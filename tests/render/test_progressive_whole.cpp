// Progressive refinement of a whole uploaded cloud (not an octree): its chunks reordered by how
// large they look (prioritizedDrawSet), drawn a few at a time on top of each other until the
// picture is complete; the finished picture is the one a single frame of every chunk draws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <span>
#include <string>
#include <utility>

#include "render/progressive.h"
#include "render/renderer.h"
#include "render/view_extent.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

// Both rasterizers, in the viewer's own look (round points sized to the local spacing, lit) as
// well as in 3-pixel squares.
TEST(ProgressiveWholeCloud, FinishedPictureEqualsASingleFullFrame) {
  headlessContext();
  const PointCloud cloud = makeWavySheet(200, {10.0, -4.0, 2.0});  // 40 000 points
  PointUploadOptions upload;
  upload.max_chunk_points = 1000;  // 40 chunks: a large file's many chunks, in small
  const GpuPointCloud gpu(cloud, upload);
  const DrawSet whole = gpu.drawSet();
  ASSERT_EQ(whole.items.size(), 40u);

  const int width = 320, height = 240;
  Camera camera = defaultCameraFor(viewExtentOf(cloud), double(width) / height);
  camera.dolly(0.6, {0.3, -0.2}, double(width) / height);  // nearer: chunk sizes differ on screen
  const View view{camera, {0, 0, width, height}};
  RenderSettings squares;
  squares.point_size_px = 3.0f;
  RenderSettings viewer = squares;
  viewer.size_mode = PointSizeMode::Adaptive;
  viewer.shape = PointShape::Round;
  viewer.lighting = true;
  for (const auto& [look, kind] :
       {std::pair{squares, RasterizerKind::Points}, std::pair{squares, RasterizerKind::Compute},
        std::pair{viewer, RasterizerKind::Compute}}) {
    RenderSettings settings = look;
    settings.rasterizer = kind;
    SCOPED_TRACE(std::string(rasterizerKindName(kind)) + ", " +
                 std::string(pointSizeModeName(settings.size_mode)));
    Renderer renderer;

    RenderTarget single(width, height);
    const FrameStats full =
        renderer.render(whole, std::span(&view, 1), settings, single.framebuffer(), width, height);
    expectDrawnBy(full, kind);

    // About three chunks a part: a budget of 3000 points at the assumed rate, never re-measured.
    ProgressiveRefinement progressive({.frame_budget_s = 1.0, .initial_points_per_second = 3000.0});
    RenderTarget parts(width, height);
    const DrawSet ordered = prioritizedDrawSet(whole, std::span(&view, 1));
    ASSERT_EQ(ordered.items.size(), whole.items.size());
    int count = 0;
    std::uint64_t points = 0;
    for (bool changed = true; count < 100; changed = false) {
      const FramePart part =
          progressive.plan(prioritizedDrawSet(whole, std::span(&view, 1)), changed);
      if (part.accumulate && part.first_item >= part.last_item) break;
      EXPECT_EQ(part.accumulate, count > 0);
      points += renderer
                    .render(ordered, std::span(&view, 1), settings, parts.framebuffer(), width,
                            height, Composition::Direct, part)
                    .points_drawn;
      ++count;
      if (progressive.complete()) break;
    }
    EXPECT_TRUE(progressive.complete());
    EXPECT_GE(count, 10) << "the picture should take many parts";
    EXPECT_EQ(points, full.points_drawn);
    const std::vector<std::uint8_t> a = single.readRgba(), b = parts.readRgba();
    ASSERT_EQ(a.size(), b.size());
    std::size_t differing = 0, covered = 0;
    for (std::size_t i = 0; i < a.size(); i += 4) {
      differing += std::memcmp(&a[i], &b[i], 3) != 0;
      covered += a[i] != 0 || a[i + 1] != 0 || a[i + 2] != 0;
    }
    EXPECT_GT(covered, std::size_t(width) * height / 10) << "the sheet is not drawn";
    EXPECT_EQ(differing, 0u) << "the refined picture differs from the single frame";
  }
}

// The chunks that look largest come first; those outside the view last.
TEST(ProgressiveWholeCloud, NearChunksComeFirstAndUnseenOnesLast) {
  headlessContext();
  const PointCloud cloud = makeWavySheet(100, {0.0, 0.0, 0.0});  // side 2 units
  PointUploadOptions upload;
  upload.max_chunk_points = 500;
  const GpuPointCloud gpu(cloud, upload);
  const DrawSet whole = gpu.drawSet();
  // Above the sheet's x < 0 half, looking straight down at it from close by: the x > 0.5 chunks
  // are outside the narrow view.
  Camera camera;
  camera.lookAt({-0.5, 0.0, 0.8}, {-0.5, 0.0, 0.0}, {0.0, 1.0, 0.0});
  camera.fov_y_deg = 40.0;
  const View view{camera, {0, 0, 200, 200}};
  const DrawSet ordered = prioritizedDrawSet(whole, std::span(&view, 1));
  ASSERT_EQ(ordered.items.size(), whole.items.size());
  // The chunks under the camera (their box holds x -0.5, y 0) before every chunk wholly in
  // the unseen x > 0 half.
  std::size_t last_under = 0, first_unseen = ordered.items.size(), under = 0, unseen = 0;
  for (std::size_t i = 0; i < ordered.items.size(); ++i) {
    const Bounds3& box = ordered.items[i].chunk->bounds;
    if (box.min[0] <= -0.5 && box.max[0] >= -0.5 && box.min[1] <= 0.0 && box.max[1] >= 0.0) {
      last_under = i, ++under;
    }
    if (box.min[0] > 0.0) first_unseen = std::min(first_unseen, i), ++unseen;
  }
  ASSERT_GT(under, 0u);
  ASSERT_GT(unseen, 0u);
  EXPECT_LT(last_under, first_unseen);
  // The same camera gives the same order: a still camera completes its picture on top.
  const DrawSet again = prioritizedDrawSet(whole, std::span(&view, 1));
  for (std::size_t i = 0; i < again.items.size(); ++i) {
    EXPECT_EQ(again.items[i].chunk, ordered.items[i].chunk);
  }
}

}  // namespace
}  // namespace parallax::test
