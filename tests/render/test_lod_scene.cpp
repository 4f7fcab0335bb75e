// The level-of-detail front: with a budget above the cloud every node is drawn once; proxies are
// expanded; a failed node hides its subtree only; the GPU budget and the per-frame upload budget
// hold; the first frame returns at once with nothing loaded.
#include "render/lod_scene.h"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <memory>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "fake_octree.h"
#include "lod/in_memory_octree.h"
#include "render/renderer.h"
#include "render_test_support.h"

namespace parallax {
namespace {

using test::FakeOctree;
using namespace std::chrono_literals;

void ensureContext() {
  test::headlessContext();
}

// Root 40 points over [0, 16]^3 with spacing 2, two full levels of 20-point nodes below it:
// 73 nodes, 1480 points. Node 8 (the root's last child) is the last with children, so it can
// be made a proxy.
std::unique_ptr<FakeOctree> twoLevels() {
  Bounds3 cube;
  cube.extend(0, 0, 0);
  cube.extend(16, 16, 16);
  auto octree = std::make_unique<FakeOctree>(cube, 40, 2.0);
  octree->addFullLevels(2, 20);
  return octree;
}

View overview() {
  View view;
  view.camera.lookAt({8, 8, 60}, {8, 8, 8}, {0, 1, 0});
  view.viewport = {0, 0, 64, 64};
  return view;
}

LodFrameSettings everything() {
  LodFrameSettings settings;
  settings.selection.point_budget = std::numeric_limits<std::uint64_t>::max();
  settings.selection.min_node_size_px = 0.0;
  return settings;
}

TEST(LodScene, ABudgetAboveTheCloudDrawsEveryNodeOnce) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  LodScene scene(octree);
  const View view = overview();
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  ASSERT_TRUE(scene.complete());
  EXPECT_EQ(draw.items.size(), 73u);
  std::set<const PointChunk*> chunks;
  std::uint64_t points = 0;
  for (const DrawItem& item : draw.items) {
    chunks.insert(item.chunk);
    points += item.chunk->count;
    // Every node's children are drawn down to the leaves: all points are sized as the leaves'.
    EXPECT_EQ(item.node_spacing, 0.5f);
  }
  EXPECT_EQ(chunks.size(), 73u);
  EXPECT_EQ(points, 1480u);
  EXPECT_EQ(draw.items[0].node_level, 0);
  EXPECT_EQ(draw.items[0].chunk->count, 40u);
  EXPECT_EQ(draw.typical_spacing, 0.5);
  EXPECT_TRUE(draw.has_colors && draw.has_intensity && !draw.has_normals);
  const LodStats& stats = scene.stats();
  EXPECT_EQ(stats.selected_nodes, 73u);
  EXPECT_EQ(stats.drawn_points, 1480u);
  EXPECT_EQ(stats.resident_nodes, 73u);
  EXPECT_EQ(stats.pending_loads, 0u);
  EXPECT_EQ(stats.failed_nodes, 0u);
  // 72 nodes of 20 points (256 + 256 + 256 bytes, and 256 for the batch box) and the root
  // (512 + 256 + 512 + 256).
  EXPECT_EQ(stats.gpu_bytes, 72u * 1024u + 1536u);
}

TEST(LodScene, ExpandsProxies) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  octree.makeProxy(8);
  ASSERT_EQ(octree.nodes().size(), 65u);
  LodScene scene(octree);
  const View view = overview();
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  EXPECT_TRUE(scene.complete());
  EXPECT_EQ(octree.expansions(), 1);
  EXPECT_EQ(octree.nodes().size(), 73u);
  EXPECT_EQ(draw.items.size(), 73u);
  EXPECT_EQ(scene.stats().drawn_points, 1480u);
}

TEST(LodScene, AProxyBehindASlowLinkIsFetchedByTheLoaderNotTheFrame) {
  ensureContext();
  Bounds3 cube;
  cube.extend(0, 0, 0);
  cube.extend(16, 16, 16);
  test::SlowLinkOctree octree(cube, 40, 2.0);
  octree.addFullLevels(2, 20);
  octree.makeProxy(8);
  LodScene scene(octree);
  const View view = overview();
  // The first frame returns at once: the proxy is not ready, the loader is asked for it.
  scene.update(std::span(&view, 1), everything());
  EXPECT_EQ(octree.expansions(), 0);
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  EXPECT_TRUE(scene.complete());
  EXPECT_EQ(octree.hierarchyLog(), (std::vector<std::string>{"fetch r7", "expand r7"}));
  EXPECT_EQ(draw.items.size(), 73u);
  EXPECT_EQ(scene.stats().drawn_points, 1480u);
}

TEST(LodScene, AFailedNodeHidesOnlyItsSubtree) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  octree.failLoads(1);  // the root's first child, "r0"
  LodScene scene(octree);
  const View view = overview();
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  EXPECT_TRUE(scene.complete());
  EXPECT_EQ(draw.items.size(), 73u - 9u);
  EXPECT_EQ(scene.stats().failed_nodes, 1u);
  EXPECT_NE(scene.firstError().find("node r0"), std::string::npos) << scene.firstError();
  // The root misses a child, so its points keep their own size; the other children are covered
  // by their drawn leaves.
  EXPECT_EQ(draw.items[0].node_level, 0);
  EXPECT_EQ(draw.items[0].node_spacing, 2.0f);
  for (std::size_t i = 1; i < draw.items.size(); ++i) EXPECT_EQ(draw.items[i].node_spacing, 0.5f);
}

TEST(LodScene, StaysUnderTheGpuBudget) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  LodSceneOptions options;
  options.gpu_budget_bytes = 13'000;  // the root (1536 bytes) and 11 nodes of 1024
  LodScene scene(octree, options);
  const View view = overview();
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  EXPECT_FALSE(scene.complete());
  EXPECT_TRUE(scene.stats().gpu_full);
  EXPECT_EQ(scene.stats().gpu_bytes, 1536u + 11u * 1024u);
  EXPECT_EQ(scene.stats().resident_nodes, 12u);
  // Uploads go parent first, so every resident node is drawn.
  EXPECT_EQ(draw.items.size(), 12u);
  // The budget holds frame after frame.
  for (int frame = 0; frame < 5; ++frame) {
    scene.update(std::span(&view, 1), everything());
    EXPECT_LE(scene.stats().gpu_bytes, 13'000u);
  }
}

TEST(LodScene, UploadsWithinTheFrameBudget) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  LodScene scene(octree);
  const View view = overview();
  LodFrameSettings settings = everything();
  settings.upload_points_per_frame = 30;  // one node a frame (at least one always goes)
  std::size_t updates = 0;
  while (!scene.complete() && updates < 100'000) {
    scene.update(std::span(&view, 1), settings);
    ++updates;
    EXPECT_LE(scene.stats().uploaded_nodes, 1u);
    if (scene.stats().uploaded_nodes == 0) std::this_thread::sleep_for(1ms);
  }
  EXPECT_TRUE(scene.complete());
  EXPECT_GE(updates, 73u);
  EXPECT_EQ(scene.stats().drawn_nodes, 73u);
}

// The viewer's switch to other attributes: a scene that stops loading keeps its last picture
// (the same items and GPU chunks, a partial picture here) and reads nothing more once
// stopLoading() has returned (the fake's loads are quick: most are read before the stop).
TEST(LodScene, StopLoadingKeepsTheLastPictureAndEndsTheReads) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  LodScene scene(octree);
  const View view = overview();
  LodFrameSettings settings = everything();
  settings.upload_points_per_frame = 30;  // one node a frame: the picture is partial for a while
  for (int updates = 0; scene.stats().drawn_nodes < 3 && updates < 100'000; ++updates) {
    scene.update(std::span(&view, 1), settings);
    if (scene.stats().uploaded_nodes == 0) std::this_thread::sleep_for(1ms);
  }
  ASSERT_GE(scene.stats().drawn_nodes, 3u);
  std::vector<std::pair<std::int32_t, const PointChunk*>> before;
  for (const DrawItem& item : scene.drawSet().items) before.emplace_back(item.node, item.chunk);
  scene.stopLoading();
  const std::size_t reads = octree.loadLog().size();
  std::vector<std::pair<std::int32_t, const PointChunk*>> after;
  for (const DrawItem& item : scene.drawSet().items) after.emplace_back(item.node, item.chunk);
  EXPECT_EQ(after, before);
  EXPECT_LT(after.size(), 73u) << "a partial picture is what must stay";
  std::this_thread::sleep_for(20ms);  // (a thread still running would read on meanwhile)
  EXPECT_EQ(octree.loadLog().size(), reads);
}

TEST(LodScene, TheFirstFrameDoesNotWaitForTheDisk) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  octree.closeGate();  // every read blocks until the gate opens
  {
    LodScene scene(octree);
    const View view = overview();
    const DrawSet& draw = scene.update(std::span(&view, 1), everything());
    EXPECT_TRUE(draw.items.empty());
    EXPECT_FALSE(scene.complete());
    EXPECT_EQ(scene.stats().selected_nodes, 73u);
    EXPECT_EQ(scene.stats().pending_loads, 73u);  // all asked for, none read
    octree.openGate();  // lets the loader finish so that the scene can be destroyed
  }
}

TEST(LodScene, ThePointBudgetLimitsWhatIsDrawn) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  LodScene scene(octree);
  const View view = overview();
  LodFrameSettings settings = everything();
  settings.selection.point_budget = 200;  // the root and its 8 children, exactly
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), settings);
  EXPECT_TRUE(scene.complete());
  EXPECT_EQ(draw.items.size(), 9u);
  EXPECT_EQ(scene.stats().drawn_points, 200u);
  EXPECT_TRUE(scene.stats().budget_reached);
  // No leaf is drawn, so the children keep their own spacing; the root's children are all
  // drawn, so its points are sized like theirs.
  for (const DrawItem& item : draw.items) EXPECT_EQ(item.node_spacing, 1.0f);
}

// Every node's points in one cloud, in node order.
PointCloud wholeCloud(const FakeOctree& octree) {
  std::vector<PointCloud> parts;
  std::uint64_t total = 0;
  for (const OctreeNode& node : octree.nodes()) {
    parts.push_back(octree.makePoints(node));
    total += parts.back().count;
  }
  PointCloud cloud;
  cloud.count = total;
  cloud.quantization = octree.info().quantization;
  cloud.positions = Column<Int3>(total);
  cloud.colors = Column<Rgba8>(total);
  cloud.intensity = Column<float>(total);
  std::size_t next = 0;
  for (const PointCloud& part : parts) {
    for (std::size_t i = 0; i < part.count; ++i, ++next) {
      cloud.positions[next] = part.positions[i];
      cloud.colors[next] = part.colors[i];
      cloud.intensity[next] = part.intensity[i];
    }
  }
  cloud.computeBounds();
  return cloud;
}

TEST(LodScene, WithTheWholeCloudSelectedTheLodRenderEqualsThePlainRender) {
  ensureContext();
  auto octree_owner = twoLevels();
  FakeOctree& octree = *octree_owner;
  const int size = 96;
  View view;
  view.camera.lookAt({-6, -10, 30}, {8, 8, 8}, {0, 0, 1});
  view.viewport = {0, 0, size, size};
  RenderSettings settings;  // fixed 1-pixel points, RGB: no size rule involved
  Renderer renderer;

  const PointCloud whole = wholeCloud(octree);
  ASSERT_EQ(whole.count, 1480u);
  GpuPointCloud plain_gpu(whole);
  RenderTarget plain_target(size, size);
  renderer.render(plain_gpu, std::span(&view, 1), settings, plain_target.framebuffer(), size, size);
  const std::vector<std::uint8_t> plain = plain_target.readRgba();

  LodScene scene(octree);
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  ASSERT_TRUE(scene.complete());
  ASSERT_EQ(scene.stats().drawn_points, 1480u);
  RenderTarget lod_target(size, size);
  const FrameStats stats =
      renderer.render(draw, std::span(&view, 1), settings, lod_target.framebuffer(), size, size);
  EXPECT_EQ(stats.points_drawn, 1480u);
  const std::vector<std::uint8_t> lod = lod_target.readRgba();

  std::size_t lit = 0, different = 0;
  for (std::size_t i = 0; i < plain.size(); i += 4) {
    lit += plain[i] || plain[i + 1] || plain[i + 2];
    different += !std::equal(&plain[i], &plain[i] + 4, &lod[i]);
  }
  EXPECT_GT(lit, 500u);  // the picture is not empty
  EXPECT_EQ(different, 0u);
}

// The same on an octree built by the real builder (lod/in_memory_octree.h): several levels of a
// 40 000-point sheet, every point in exactly one node.
TEST(LodScene, ABuiltOctreeRendersLikeTheCloud) {
  ensureContext();
  const PointCloud sheet = test::makeWavySheet(200, {500000.0, 4000000.0, 100.0});
  OctreeBuildOptions options;
  options.max_node_points = 500;
  options.spacing = 0.2;  // coarse at the top, so the sheet spreads over 5 levels
  const std::unique_ptr<InMemoryOctree> octree = buildOctree(sheet, options);
  ASSERT_GT(octree->nodes().size(), 9u);
  int deepest = 0;
  for (const OctreeNode& node : octree->nodes()) deepest = std::max(deepest, node.level);
  EXPECT_GE(deepest, 3);
  const int size = 128;
  View view;
  view.viewport = {0, 0, size, size};
  view.camera = defaultCameraFor(sheet.bounds, 1.0);
  RenderSettings settings;
  Renderer renderer;

  GpuPointCloud plain_gpu(sheet);
  RenderTarget plain_target(size, size);
  renderer.render(plain_gpu, std::span(&view, 1), settings, plain_target.framebuffer(), size, size);
  const std::vector<std::uint8_t> plain = plain_target.readRgba();

  LodScene scene(*octree);
  const DrawSet& draw = scene.finishLoading(std::span(&view, 1), everything());
  ASSERT_TRUE(scene.complete());
  EXPECT_EQ(scene.stats().drawn_nodes, octree->nodes().size());
  EXPECT_EQ(scene.stats().drawn_points, 40'000u);
  RenderTarget lod_target(size, size);
  renderer.render(draw, std::span(&view, 1), settings, lod_target.framebuffer(), size, size);
  const std::vector<std::uint8_t> lod = lod_target.readRgba();
  std::size_t lit = 0, different = 0;
  for (std::size_t i = 0; i < plain.size(); i += 4) {
    lit += plain[i] || plain[i + 1] || plain[i + 2];
    different += !std::equal(&plain[i], &plain[i] + 4, &lod[i]);
  }
  EXPECT_GT(lit, 2000u);
  EXPECT_EQ(different, 0u);
}

}  // namespace
}  // namespace parallax
