// `parallax bench render DIR --budget N`: the frame time of a level-of-detail frame once loading
// is complete, beside a same-run reference: the very points the frame draws, merged into one
// GpuPointCloud (Morton-ordered chunks, as `parallax render FILE` uploads a file) and drawn
// plainly. The difference is what streaming costs per frame: the node selection in update(), one
// draw call per node instead of per 1 M-point chunk, and the nodes' less compact order.
//
// The camera frames the whole cloud (the default view of `parallax view DIR`). Mono and, with
// --stereo MODE, that stereo mode: one selection on the union of the eyes' frusta, both eyes
// drawn. Timed to glFinish, median of --repeat frames after a warm-up frame; update and draw
// are timed apart.
#include "bench_render_lod.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

#include "lod/octree_open.h"
#include "lod/octree_url.h"
#include "network_options.h"
#include "render/gl_context.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/renderer.h"
#include "render/view_extent.h"

namespace parallax::cli {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The points of `nodes` as one cloud (positions and colours), for the plain reference.
PointCloud mergeNodes(const Octree& octree, const std::vector<std::int32_t>& nodes) {
  std::uint64_t count = 0;
  for (const std::int32_t node : nodes) count += octree.nodes()[std::size_t(node)].point_count;
  PointCloud merged;
  merged.count = count;
  merged.quantization = octree.info().quantization;
  merged.positions = Column<Int3>(count);
  if (octree.info().has_colors) merged.colors = Column<Rgba8>(count);
  std::uint64_t at = 0;
  for (const std::int32_t node : nodes) {
    const PointCloud part = octree.loadNode(octree.nodes()[std::size_t(node)]);
    std::memcpy(&merged.positions[at], part.positions.data(), part.count * sizeof(Int3));
    if (merged.hasColors() && part.hasColors()) {
      std::memcpy(&merged.colors[at], part.colors.data(), part.count * sizeof(Rgba8));
    }
    at += part.count;
  }
  merged.computeBounds();
  return merged;
}

void benchFrame(const LodRenderBenchOptions& o, Octree& octree, const Camera& camera,
                const StereoSettings& stereo, const RenderSettings& settings) {
  const StereoFrame frame = stereoFrame(camera, stereo, o.width, o.height);
  LodFrameSettings lod_settings;
  lod_settings.selection.point_budget = o.budget;
  lod_settings.selection.min_node_size_px = o.min_node_size;
  LodScene scene(octree);
  RenderTarget target(o.width, o.height);
  Renderer renderer;

  auto start = Clock::now();
  scene.finishLoading(frame.views, lod_settings);
  const double load_s = secondsSince(start);
  const LodStats loaded = scene.stats();
  printNetworkReport("bench render", octree, loaded.drawn_points);

  std::vector<double> update_times, draw_times, plain_times;
  for (int i = 0; i <= o.repeat; ++i) {  // frame 0: warm-up
    start = Clock::now();
    const DrawSet& draw_set = scene.update(frame.views, lod_settings);
    const double update_s = secondsSince(start);
    start = Clock::now();
    renderer.render(draw_set, frame, settings, target.framebuffer(), o.width, o.height);
    glFinish();
    if (i > 0) update_times.push_back(update_s), draw_times.push_back(secondsSince(start));
  }

  // The reference: the same nodes' points as one plainly drawn cloud.
  std::vector<SelectionView> views;
  for (const View& view : frame.views) {
    views.push_back(selectionViewFor(view, octree.info().bounds));
  }
  const NodeSelection selection = selectNodes(octree.nodes(), views, lod_settings.selection, {});
  const GpuPointCloud plain(mergeNodes(octree, selection.nodes));
  const DrawSet plain_set = plain.drawSet();
  Renderer plain_renderer;
  for (int i = 0; i <= o.repeat; ++i) {
    start = Clock::now();
    plain_renderer.render(plain_set, frame, settings, target.framebuffer(), o.width, o.height);
    glFinish();
    if (i > 0) plain_times.push_back(secondsSince(start));
  }
  const double update_s = median(update_times), draw_s = median(draw_times);
  const double plain_s = median(plain_times);
  std::printf(
      "%-6s loaded in %.2f s: %zu nodes, %.2f M points drawn (plain reference %.2f M)\n"
      "       update %6.1f ms + draw %6.1f ms = LOD frame %6.1f ms   plain %6.1f ms   "
      "LOD / plain %.2f\n",
      std::string(stereoModeName(stereo.mode)).c_str(), load_s, loaded.drawn_nodes,
      double(loaded.drawn_points) / 1e6, double(plain.pointCount()) / 1e6, update_s * 1e3,
      draw_s * 1e3, (update_s + draw_s) * 1e3, plain_s * 1e3, (update_s + draw_s) / plain_s);
}

}  // namespace

int runBenchRenderLod(const LodRenderBenchOptions& o) {
  checkOctreeUrl(o.directory);
  auto octree = openOctree(o.directory);
  auto context = GlContext::createHeadless();
  std::printf("bench render: %s, %llu points, budget %llu, %dx%d, median of %d frames, on %s\n",
              o.directory.c_str(), static_cast<unsigned long long>(octree->info().point_count),
              static_cast<unsigned long long>(o.budget), o.width, o.height, o.repeat,
              context->renderer().c_str());
  const Camera camera = defaultCameraFor(viewExtentOf(*octree), double(o.width) / o.height);
  RenderSettings settings;
  settings.color = ColorMode::Rgb;
  benchFrame(o, *octree, camera, {}, settings);
  for (const StereoMode mode : o.stereo) {
    StereoSettings stereo;
    stereo.mode = mode;
    benchFrame(o, *octree, camera, stereo, settings);
  }
  return 0;
}

}  // namespace parallax::cli
