// `parallax bench render DIR --budget N`: the frame time of a level-of-detail frame once loading
// is complete, beside a same-run reference: the very points the frame draws, merged into one
// GpuPointCloud (Morton-ordered chunks, as `parallax render FILE` uploads a file) and drawn
// plainly. The difference is what streaming costs per frame: the node selection in update(), one
// draw call per node instead of per 1 M-point chunk, and the nodes' less compact order.
//
// The camera frames the whole cloud (the default view of `parallax view DIR`). Mono and, with
// --stereo MODE, each stereo mode given: one selection on the union of the eyes' frusta, both
// eyes drawn; the sides' frames alternated (mono, then each mode, round after round), so that
// a shared machine's load weighs on all alike, and each mode's median against mono's. Timed to
// glFinish, median of --repeat frames after a warm-up round; update and draw are timed apart
// (--pass-times: the compute rasterizer's passes too).
//
// --orbit N: what the viewer does while the user orbits: N frames, the camera turning 2 degrees
// a frame around the cloud's centre, each frame LodScene::update() (streaming, never waiting)
// and the renderer, with progressive refinement (render/progressive.h) within --frame-budget ms
// when given; then, the camera still, the frames until the picture is complete. Prints the
// frame times (median, 90th percentile, worst) and the points drawn a frame; with --json, one
// JSON object instead (median_ms, p90_ms, worst_ms, the look, which rasterizer drew and whether
// with 64-bit atomics). The orbit draws in the stereo mode of --stereo MODE (one mode).
#include "bench_render_lod.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>
#include "bench_pass_times.h"
#include "bench_render_orbit.h"
#include "bench_timing.h"
#include "network_options.h"
#include "render/frame_step.h"
#include "render/gl_context.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/progressive.h"
#include "render/renderer.h"
#include "render/view_extent.h"

namespace parallax::cli {
namespace {

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

// One side of the comparison: mono or a stereo mode, with its own scene (its views' nodes) and
// renderer (the composed modes' canvas is twice as wide: one renderer for both sizes would
// reallocate its framebuffers every frame).
struct FrameSide {
  StereoFrame frame;
  LodScene scene;
  Renderer renderer;
  std::vector<double> update_times, draw_times, plain_times;
  std::vector<ComputePassTimes> passes;
  FrameSide(const StereoFrame& views, Octree& octree, const ComputeRasterizerOptions& compute)
      : frame(views), scene(octree), renderer(compute) {}
};

// Mono and each stereo mode of o.stereo, frames alternated side by side (mono, sbs, mono, sbs,
// ...) so that the load of a shared machine weighs on every side alike, then the same for the
// plain references; the medians and each mode's ratio to mono.
void benchFrames(const LodRenderBenchOptions& o, Octree& octree, const Camera& camera,
                 const RenderSettings& settings) {
  LodFrameSettings lod_settings;
  lod_settings.selection.point_budget = o.budget;
  lod_settings.selection.min_node_size_px = o.min_node_size;
  RenderTarget target(o.width, o.height);
  std::vector<std::unique_ptr<FrameSide>> sides;
  std::vector<StereoSettings> modes(1);  // mono first
  for (const StereoMode mode : o.stereo) {
    StereoSettings stereo;
    stereo.mode = mode;
    modes.push_back(stereo);
  }
  std::vector<double> load_s;
  std::vector<LodStats> loaded;
  for (const StereoSettings& mode : modes) {
    sides.push_back(std::make_unique<FrameSide>(stereoFrame(camera, mode, o.width, o.height),
                                                octree, o.compute));
    const auto start = Clock::now();
    sides.back()->scene.finishLoading(sides.back()->frame.views, lod_settings);
    load_s.push_back(secondsSince(start));
    loaded.push_back(sides.back()->scene.stats());
    printNetworkReport("bench render", octree, loaded.back().drawn_points);
  }
  const std::vector<double> load_before = loadAverage();
  for (int i = 0; i <= o.repeat; ++i) {  // round 0: warm-up
    for (auto& side : sides) {
      auto start = Clock::now();
      const DrawSet& draw_set = side->scene.update(side->frame.views, lod_settings);
      const double update_s = secondsSince(start);
      start = Clock::now();
      const FrameStats stats = side->renderer.render(draw_set, side->frame, settings,
                                                     target.framebuffer(), o.width, o.height);
      glFinish();
      if (i == 0) continue;
      side->update_times.push_back(update_s), side->draw_times.push_back(secondsSince(start));
      if (o.compute.time_passes && stats.rasterizer == RasterizerKind::Compute) {
        side->passes.push_back(side->renderer.computeRasterizer().passTimesOfLastFrame());
      }
    }
  }

  // The references: the same nodes' points as one plainly drawn cloud, per side.
  std::vector<std::unique_ptr<GpuPointCloud>> plains;
  for (auto& side : sides) {
    std::vector<SelectionView> views;
    for (const View& view : side->frame.views) {
      views.push_back(selectionViewFor(view, octree.info().bounds));
    }
    const NodeSelection selection = selectNodes(octree.nodes(), views, lod_settings.selection, {});
    plains.push_back(std::make_unique<GpuPointCloud>(mergeNodes(octree, selection.nodes)));
  }
  std::vector<DrawSet> plain_sets;
  std::vector<std::unique_ptr<Renderer>> plain_renderers;
  for (const auto& plain : plains) {
    plain_sets.push_back(plain->drawSet());
    plain_renderers.push_back(std::make_unique<Renderer>(o.compute));
  }
  for (int i = 0; i <= o.repeat; ++i) {
    for (std::size_t s = 0; s < sides.size(); ++s) {
      const auto start = Clock::now();
      plain_renderers[s]->render(plain_sets[s], sides[s]->frame, settings, target.framebuffer(),
                                 o.width, o.height);
      glFinish();
      if (i > 0) sides[s]->plain_times.push_back(secondsSince(start));
    }
  }
  const std::vector<double> load_after = loadAverage();

  double mono_draw = 0, mono_frame = 0;
  for (std::size_t s = 0; s < sides.size(); ++s) {
    const FrameSide& side = *sides[s];
    const double update_s = median(side.update_times), draw_s = median(side.draw_times);
    const double plain_s = median(side.plain_times);
    const std::string mode(stereoModeName(modes[s].mode));
    std::printf(
        "%-6s loaded in %.2f s: %zu nodes, %.2f M points drawn (plain reference %.2f M)\n"
        "       update %6.1f ms + draw %6.1f ms = LOD frame %6.1f ms   plain %6.1f ms   "
        "LOD / plain %.2f\n",
        mode.c_str(), load_s[s], loaded[s].drawn_nodes, double(loaded[s].drawn_points) / 1e6,
        double(plains[s]->pointCount()) / 1e6, update_s * 1e3, draw_s * 1e3,
        (update_s + draw_s) * 1e3, plain_s * 1e3, (update_s + draw_s) / plain_s);
    if (!side.passes.empty()) printPassTimes(mode.c_str(), side.passes);
    if (s == 0) {
      mono_draw = draw_s, mono_frame = update_s + draw_s;
    } else {
      std::printf("       %s / mono: draw %.2fx, LOD frame %.2fx\n", mode.c_str(),
                  draw_s / mono_draw, (update_s + draw_s) / mono_frame);
    }
  }
  if (sides.size() > 1) {
    std::printf("(medians of %d frames of each, alternated; load %.2f before, %.2f after)\n",
                o.repeat, load_before[0], load_after[0]);
  }
}

void benchOrbit(const LodRenderBenchOptions& o, Octree& octree, Camera camera) {
  LodFrameSettings lod_settings;
  lod_settings.selection.point_budget = o.budget;
  lod_settings.selection.min_node_size_px = o.min_node_size;
  LodScene scene(octree);
  RenderTarget target(o.width, o.height);
  Renderer renderer(o.compute);
  ProgressiveSettings progressive_settings;
  if (o.frame_budget_ms > 0) progressive_settings.frame_budget_s = o.frame_budget_ms / 1e3;
  ProgressiveRefinement progressive(progressive_settings);
  const bool refine = o.frame_budget_ms > 0;
  std::vector<double> frame_times, points_drawn;
  std::string rasterizer;
  bool atomic64 = false;
  auto frame = [&](bool moving) {
    const auto start = Clock::now();
    const StereoFrame views = stereoFrame(camera, o.orbit_stereo, o.width, o.height);
    const DrawSet& draw_set = scene.update(views.views, lod_settings);
    // The viewer's own frame step (render/frame_step.h).
    const FrameStats stats =
        drawFrameStep(renderer, refine ? &progressive : nullptr, draw_set, views, o.settings,
                      target.framebuffer(), o.width, o.height, moving)
            .stats;
    glFinish();
    rasterizer = stats.rasterizer == RasterizerKind::Compute ? "compute" : "points";
    // Asked only where compute drew (computeRasterizer() would make one).
    atomic64 = stats.rasterizer == RasterizerKind::Compute &&
               renderer.computeRasterizer().uses64BitAtomics();
    return std::pair<double, std::uint64_t>(secondsSince(start), stats.points_drawn);
  };
  // Warm-up: the first picture of the whole cloud, loaded (what the viewer shows first).
  const std::vector<double> load_before = loadAverage();
  scene.finishLoading(stereoFrame(camera, o.orbit_stereo, o.width, o.height).views, lod_settings);
  frame(true);
  for (int i = 0; i < o.orbit_frames; ++i) {
    orbitStep(camera);
    const auto [seconds, points] = frame(true);
    frame_times.push_back(seconds);
    points_drawn.push_back(double(points));
  }
  // The camera stops: frames until the picture is complete (and streaming has caught up).
  const auto stop = Clock::now();
  int still_frames = 0;
  while (still_frames < 200 && (!scene.complete() || (refine && !progressive.complete()))) {
    frame(false);
    ++still_frames;
  }
  const double complete_s = secondsSince(stop);
  const FrameTimeSummary t = summarizeFrames(frame_times);
  if (o.json) {
    const nlohmann::json result = {
        {"bench", "render"},
        {"mode", "orbit"},
        {"input", o.directory},
        {"points", octree.info().point_count},
        {"budget", o.budget},
        {"frame_budget_ms", o.frame_budget_ms},
        {"width", o.width},
        {"height", o.height},
        {"frames", t.frames},
        {"degrees_per_frame", kOrbitDegreesPerFrame},
        {"asked", rasterizerKindName(o.settings.rasterizer)},
        {"rasterizer", rasterizer},
        {"atomic64", atomic64},
        {"allow_atomic64", o.compute.allow_64bit_atomics},
        {"settings", lookJson(o.look, o.settings, o.orbit_stereo)},
        {"median_ms", t.median_ms},
        {"p90_ms", t.p90_ms},
        {"worst_ms", t.worst_ms},
        {"points_drawn", percentile(points_drawn, 0.5)},
        {"still_frames", still_frames},
        {"complete_ms", complete_s * 1e3},
        {"load_average", {{"before", load_before}, {"after", loadAverage()}}}};
    std::printf("%s\n", result.dump().c_str());
    return;
  }
  std::printf("look (%s): %s\n", o.look.c_str(), lookLine(o.settings, o.orbit_stereo).c_str());
  std::printf(
      "orbit  %d frames (%s%s): frame median %.1f ms, p90 %.1f ms, worst %.1f ms; points a "
      "frame median %.2f M; still: complete after %d frames, %.0f ms\n",
      o.orbit_frames, rasterizer.c_str(),
      refine ? (", budget " + std::to_string(int(o.frame_budget_ms)) + " ms").c_str() : "",
      t.median_ms, t.p90_ms, t.worst_ms, percentile(points_drawn, 0.5) / 1e6, still_frames,
      complete_s * 1e3);
}

// The time to the first frame that draws points and to the whole load (finishLoading), the
// nodes read with `selection`: what the viewer's first picture waits for.
struct LoadTimes {
  double first_s = 0, loaded_s = 0;
  std::uint64_t points = 0;
};

LoadTimes timeLoad(const LodRenderBenchOptions& o, Octree& octree,
                   const AttributeSelection& selection) {
  octree.selectAttributes(selection);  // (no loader reads it: the last scene has ended)
  const StereoFrame frame = stereoFrame(o.camera, {}, o.width, o.height);
  LodFrameSettings lod_settings;
  lod_settings.selection.point_budget = o.budget;
  lod_settings.selection.min_node_size_px = o.min_node_size;
  RenderTarget target(o.width, o.height);
  Renderer renderer(o.compute);
  LoadTimes times;
  const auto start = Clock::now();
  LodScene scene(octree);
  for (;;) {
    const DrawSet& draw_set = scene.update(frame.views, lod_settings);
    renderer.render(draw_set, frame, o.settings, target.framebuffer(), o.width, o.height);
    glFinish();
    if (scene.stats().drawn_points > 0 || scene.complete()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // as a frame loop would wait
  }
  times.first_s = secondsSince(start);
  scene.finishLoading(frame.views, lod_settings);
  times.loaded_s = secondsSince(start);
  times.points = scene.stats().drawn_points;
  return times;
}

void benchSelectiveLoad(const LodRenderBenchOptions& o, Octree& octree) {
  const AttributeSelection drawn = attributesDrawn(o.settings);
  std::string names = "x y z";
  for (const std::string& name : drawn.names()) {
    names += ' ';  // (appended: GCC 12's -Wrestrict misreads " " + name, bug 105329)
    names += name;
  }
  std::vector<double> first_all, first_drawn, loaded_all, loaded_drawn;
  std::uint64_t points_all = 0, points_drawn = 0;
  for (int round = 0; round <= o.repeat; ++round) {  // round 0: warm-up
    const LoadTimes all = timeLoad(o, octree, AttributeSelection());
    const LoadTimes selected = timeLoad(o, octree, drawn);
    if (round == 0) continue;
    first_all.push_back(all.first_s), loaded_all.push_back(all.loaded_s);
    first_drawn.push_back(selected.first_s), loaded_drawn.push_back(selected.loaded_s);
    points_all = all.points, points_drawn = selected.points;
  }
  octree.selectAttributes(AttributeSelection());
  const double fa = median(first_all), fd = median(first_drawn);
  const double la = median(loaded_all), ld = median(loaded_drawn);
  std::printf(
      "nodes read with %s against every attribute, median of %d rounds each, alternating:\n"
      "  first picture %7.1f ms against %7.1f ms (%.2fx)\n"
      "  whole load    %7.1f ms against %7.1f ms (%.2fx), %.2f M points drawn (%.2f M)\n",
      names.c_str(), o.repeat, fd * 1e3, fa * 1e3, fa / fd, ld * 1e3, la * 1e3, la / ld,
      double(points_drawn) / 1e6, double(points_all) / 1e6);
}

}  // namespace

int runBenchRenderLod(const LodRenderBenchOptions& o, Octree& octree) {
  auto context = GlContext::createHeadless();
  if (!o.json) {
    std::printf("bench render: %s, %llu points, budget %llu, %dx%d, median of %d frames, on %s\n",
                o.directory.c_str(), static_cast<unsigned long long>(octree.info().point_count),
                static_cast<unsigned long long>(o.budget), o.width, o.height, o.repeat,
                context->renderer().c_str());
  }
  if (o.orbit_frames > 0) {
    benchOrbit(o, octree, o.camera);
    return 0;
  }
  if (o.selective_load) {
    benchSelectiveLoad(o, octree);
    return 0;
  }
  benchFrames(o, octree, o.camera, o.settings);
  return 0;
}

}  // namespace parallax::cli
