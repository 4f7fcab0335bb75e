// Level-of-detail frame costs on a generated cloud: builds the octree in memory, then streams it
// through LodScene into a headless renderer and prints the time to the first complete picture
// and, for a camera orbiting the cloud, the per-frame costs of update() (selection, uploads) and
// of drawing, beside the points drawn.
//
//   build/bench/bench_lod_scene [points=10000000] [budget=3000000] [width=1920] [height=1080]
//                               [frames=24]
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "lod/in_memory_octree.h"
#include "render/gl_context.h"
#include "render/lod_scene.h"
#include "render/renderer.h"
#include "synth/scene_generator.h"

namespace {

using namespace parallax;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The generated scene with positions and colours (the generator's normals are left out).
PointCloud generate(std::uint64_t points) {
  synth::SceneGenerator generator({});
  PointCloud cloud;
  cloud.count = points;
  cloud.quantization = generator.quantization();
  cloud.positions = Column<Int3>(points);
  cloud.colors = Column<Rgba8>(points);
  const std::uint64_t block_points = synth::SceneGenerator::kBlockPoints;
  const std::uint64_t blocks = (points + block_points - 1) / block_points;
  tbb::parallel_for(std::uint64_t{0}, blocks, [&](std::uint64_t block) {
    const std::uint64_t first = block * block_points;
    const std::size_t count = std::size_t(std::min(block_points, points - first));
    const PointCloud part = generator.generateBlock(block, count);
    std::memcpy(&cloud.positions[first], part.positions.data(), count * sizeof(Int3));
    if (part.hasColors()) {
      std::memcpy(&cloud.colors[first], part.colors.data(), count * sizeof(Rgba8));
      return;
    }
    // The export layout: colours as the scalar columns red, green, blue.
    const ScalarColumn *red = part.findScalar("red"), *green = part.findScalar("green"),
                       *blue = part.findScalar("blue");
    for (std::size_t i = 0; i < count; ++i) {
      cloud.colors[first + i] = {red ? red->as<std::uint8_t>()[i] : std::uint8_t(255),
                                 green ? green->as<std::uint8_t>()[i] : std::uint8_t(255),
                                 blue ? blue->as<std::uint8_t>()[i] : std::uint8_t(255), 255};
    }
  });
  cloud.computeBounds();
  return cloud;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  auto arg = [&](int i, std::uint64_t fallback) {
    return argc > i ? std::strtoull(argv[i], nullptr, 10) : fallback;
  };
  const std::uint64_t points = arg(1, 10'000'000), budget = arg(2, 3'000'000);
  const int width = int(arg(3, 1920)), height = int(arg(4, 1080)), frames = int(arg(5, 24));

  auto start = Clock::now();
  const PointCloud cloud = generate(points);
  std::printf("generate  %llu points: %.0f ms\n", (unsigned long long)points, msSince(start));
  start = Clock::now();
  const std::unique_ptr<InMemoryOctree> octree = buildOctree(cloud);
  std::printf("octree    %zu nodes: %.0f ms (%.2f M points/s)\n", octree->nodes().size(),
              msSince(start), double(points) / msSince(start) / 1e3);

  const auto context = GlContext::createHeadless();
  Renderer renderer;
  RenderTarget target(width, height);
  View view;
  view.viewport = {0, 0, width, height};
  view.camera = defaultCameraFor(octree->info().bounds, view.aspect());
  RenderSettings settings;
  settings.size_mode = PointSizeMode::Adaptive;
  LodFrameSettings frame_settings;
  frame_settings.selection.point_budget = budget;
  LodScene scene(*octree);

  start = Clock::now();
  const DrawSet& first = scene.finishLoading(std::span(&view, 1), frame_settings);
  renderer.render(first, std::span(&view, 1), settings, target.framebuffer(), width, height);
  glFinish();
  std::printf("first complete picture: %.0f ms, %zu nodes, %llu points drawn\n", msSince(start),
              scene.stats().drawn_nodes, (unsigned long long)scene.stats().drawn_points);

  // Orbit: 5 degrees a frame, so every frame needs some new nodes.
  std::vector<double> update_ms, render_ms;
  std::uint64_t drawn = 0, uploaded = 0;
  for (int frame = 0; frame < frames; ++frame) {
    view.camera.orbit(0.0872665, 0.0, OrbitMode::Turntable);
    start = Clock::now();
    const DrawSet& draw = scene.update(std::span(&view, 1), frame_settings);
    update_ms.push_back(msSince(start));
    start = Clock::now();
    renderer.render(draw, std::span(&view, 1), settings, target.framebuffer(), width, height);
    glFinish();
    render_ms.push_back(msSince(start));
    drawn += scene.stats().drawn_points, uploaded += scene.stats().uploaded_points;
  }
  std::printf(
      "orbit, %d frames at %dx%d, budget %llu: update %.1f ms, draw %.1f ms (medians), "
      "%.2f M points drawn and %.2f M uploaded a frame on average\n",
      frames, width, height, (unsigned long long)budget, median(update_ms), median(render_ms),
      double(drawn) / frames / 1e6, double(uploaded) / frames / 1e6);

  // Approach: 15 % closer a frame, towards the centre of the picture; new detail every frame.
  update_ms.clear(), render_ms.clear();
  drawn = 0, uploaded = 0;
  std::uint64_t pending = 0;
  for (int frame = 0; frame < frames; ++frame) {
    view.camera.dolly(0.85, {0.0, 0.0}, view.aspect());
    start = Clock::now();
    const DrawSet& draw = scene.update(std::span(&view, 1), frame_settings);
    update_ms.push_back(msSince(start));
    start = Clock::now();
    renderer.render(draw, std::span(&view, 1), settings, target.framebuffer(), width, height);
    glFinish();
    render_ms.push_back(msSince(start));
    drawn += scene.stats().drawn_points, uploaded += scene.stats().uploaded_points;
    pending += scene.stats().pending_loads;
  }
  std::printf(
      "approach, %d frames: update %.1f ms, draw %.1f ms (medians), %.2f M points drawn, "
      "%.2f M uploaded, %.0f nodes pending a frame on average\n",
      frames, median(update_ms), median(render_ms), double(drawn) / frames / 1e6,
      double(uploaded) / frames / 1e6, double(pending) / frames);
  start = Clock::now();
  scene.finishLoading(std::span(&view, 1), frame_settings);
  std::printf("then complete after %.0f ms more: %zu nodes, %.2f M points drawn\n", msSince(start),
              scene.stats().drawn_nodes, double(scene.stats().drawn_points) / 1e6);
  std::printf("gpu cache: %.0f MB, %zu nodes resident, %llu evictions\n",
              double(scene.stats().gpu_bytes) / 1e6, scene.stats().resident_nodes,
              (unsigned long long)scene.stats().evictions);
  return 0;
}
