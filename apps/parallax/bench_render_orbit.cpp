#include "bench_render_orbit.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <glm/glm.hpp>
#include <string>

#include "bench_timing.h"
#include "render/frame_step.h"
#include "render/progressive.h"
#include "render/renderer.h"

namespace parallax::cli {

void orbitStep(Camera& camera) {
  const glm::dvec3 up = camera.world_up;
  camera.orbit(glm::radians(kOrbitDegreesPerFrame), 0.0, OrbitMode::Turntable);
  camera.world_up = up;
}

FrameTimeSummary summarizeFrames(const std::vector<double>& seconds) {
  FrameTimeSummary summary;
  summary.frames = int(seconds.size());
  if (seconds.empty()) return summary;
  summary.median_ms = percentile(seconds, 0.5) * 1e3;
  summary.p90_ms = percentile(seconds, 0.9) * 1e3;
  summary.worst_ms = percentile(seconds, 1.0) * 1e3;
  return summary;
}

nlohmann::json lookJson(const std::string& look, const RenderSettings& s,
                        const StereoSettings& stereo) {
  return {{"look", look},
          {"size_mode", pointSizeModeName(s.size_mode)},
          {"point_size", s.point_size_px},
          {"adaptive_scale", s.adaptive_scale},
          {"world_size", s.world_size},
          {"shape", pointShapeName(s.shape)},
          {"lighting", s.lighting},
          {"edl", s.edl},
          {"color", colorModeName(s.color)},
          {"msaa", s.samples},
          {"hq", s.hq},
          {"filter", !(s.filter == PointFilter{})},
          {"stereo", stereoModeName(stereo.mode)}};
}

std::string lookLine(const RenderSettings& s, const StereoSettings& stereo) {
  char size[64];
  switch (s.size_mode) {
    case PointSizeMode::Fixed:
      std::snprintf(size, sizeof size, "fixed %g px", double(s.point_size_px));
      break;
    case PointSizeMode::Attenuated:
      std::snprintf(size, sizeof size, "attenuated %g", double(s.world_size));
      break;
    case PointSizeMode::Adaptive:
      std::snprintf(size, sizeof size, "adaptive x%g", double(s.adaptive_scale));
      break;
  }
  std::string line = "size ";
  line += size;
  line += ", ";
  line += pointShapeName(s.shape);
  line += s.lighting ? ", lit" : ", unlit";
  line += ", colour ";
  line += colorModeName(s.color);
  line += s.edl ? ", EDL" : ", no EDL";
  if (s.samples > 1) line += ", msaa " + std::to_string(s.samples);
  if (s.hq) line += ", hq";
  if (!(s.filter == PointFilter{})) line += ", filtered";
  line += ", ";
  line += stereoModeName(stereo.mode);
  return line;
}

namespace {

struct Side {
  std::vector<double> wall, cpu;
  FrameStats stats;  // the last frame's
};

void timedFrame(Renderer& renderer, const DrawSet& draw_set, const StereoFrame& frame,
                const RenderSettings& settings, const RenderTarget& target, int width, int height,
                Side& side) {
  const auto start = Clock::now();
  const double cpu_start = processCpuSeconds();
  side.stats = renderer.render(draw_set, frame, settings, target.framebuffer(), width, height);
  glFinish();
  side.wall.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  side.cpu.push_back(processCpuSeconds() - cpu_start);
}

// The viewer's step: the part of the prioritized draw set that progressive refinement plans.
void timedViewerFrame(Renderer& renderer, ProgressiveRefinement& progressive,
                      const DrawSet& draw_set, const StereoFrame& frame,
                      const RenderSettings& settings, const RenderTarget& target, int width,
                      int height, bool changed, Side& side) {
  const auto start = Clock::now();
  const double cpu_start = processCpuSeconds();
  const DrawSet prioritized = prioritizedDrawSet(draw_set, frame.views);
  const FrameStepResult step = drawFrameStep(renderer, &progressive, prioritized, frame, settings,
                                             target.framebuffer(), width, height, changed);
  glFinish();
  side.wall.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  side.cpu.push_back(processCpuSeconds() - cpu_start);
  if (step.drew) side.stats = step.stats;
}

const char* rasterizerLabel(RasterizerKind kind) {
  return kind == RasterizerKind::Compute ? "compute" : "points";
}

void printRow(const char* name, const Side& side, const FrameTimeSummary& t) {
  std::printf("%-30s %-8s %9.1f %9.1f %9.1f %9.1f %11.2f\n", name,
              rasterizerLabel(side.stats.rasterizer), t.median_ms, t.p90_ms, t.worst_ms,
              median(side.cpu) * 1e3,
              t.median_ms > 0 ? double(side.stats.points_drawn) / t.median_ms / 1e3 : 0.0);
}

}  // namespace

int runBenchRenderFileOrbit(const FileOrbitBenchOptions& o, const DrawSet& draw_set,
                            Camera camera) {
  const std::vector<double> load_before = loadAverage();
  Renderer ours(o.compute), reference(o.compute);
  RenderTarget target(o.width, o.height);
  const int w = o.width, h = o.height;

  // Warm-up (shaders, framebuffers, the first touch of the buffers), which also says who draws.
  Side look, plain;
  StereoFrame frame = stereoFrame(camera, o.stereo, w, h);
  ProgressiveSettings progressive_settings;
  const bool refine = o.frame_budget_ms > 0;
  if (refine) progressive_settings.frame_budget_s = o.frame_budget_ms / 1e3;
  ProgressiveRefinement progressive(progressive_settings);
  // The viewer's first frame is planned too (and measures the rate for the next).
  if (refine) {
    timedViewerFrame(ours, progressive, draw_set, frame, o.settings, target, w, h, true, look);
  } else {
    timedFrame(ours, draw_set, frame, o.settings, target, w, h, look);
  }
  RenderSettings reference_settings = o.settings;
  std::string reference_name = "same look, GL_POINTS";
  if (look.stats.rasterizer == RasterizerKind::Points) {
    // GL_POINTS drew the look: the reference is render's plain look (same colours and filter).
    reference_settings = RenderSettings{};
    reference_settings.color = o.settings.color;
    reference_settings.uniform_color = o.settings.uniform_color;
    reference_settings.background = o.settings.background;
    reference_settings.filter = o.settings.filter;
    reference_name = "1-px squares, unlit, GL_POINTS";
  }
  reference_settings.rasterizer = RasterizerKind::Points;
  timedFrame(reference, draw_set, frame, reference_settings, target, w, h, plain);
  look = Side{}, plain = Side{};

  for (int i = 0; i < o.frames; ++i) {
    if (o.degrees_per_frame > 0) orbitStep(camera);
    frame = stereoFrame(camera, o.stereo, w, h);
    // Each side goes first every other frame: neither always meets a cache the other warmed.
    for (int turn = 0; turn < 2; ++turn) {
      if ((turn == 0) == (i % 2 == 0)) {
        if (refine) {
          timedViewerFrame(ours, progressive, draw_set, frame, o.settings, target, w, h,
                           o.degrees_per_frame > 0 || i == 0, look);
        } else {
          timedFrame(ours, draw_set, frame, o.settings, target, w, h, look);
        }
      } else {
        timedFrame(reference, draw_set, frame, reference_settings, target, w, h, plain);
      }
    }
  }
  const std::vector<double> load_after = loadAverage();
  const FrameTimeSummary t = summarizeFrames(look.wall), r = summarizeFrames(plain.wall);
  const bool compute = look.stats.rasterizer == RasterizerKind::Compute;
  // Only asked of a compute rasterizer that drew (computeRasterizer() would make one).
  const bool atomic64 = compute && ours.computeRasterizer().uses64BitAtomics();
  // Splats of the look's last frame wider than an inline splat (read back once, after the run).
  const std::uint64_t large_splats =
      compute ? ours.computeRasterizer().largeSplatsOfLastFrame() : 0;
  const double ratio = t.median_ms > 0 ? r.median_ms / t.median_ms : 0.0;
  const char* motion = o.degrees_per_frame > 0 ? "orbit" : "still";

  if (o.json) {
    const nlohmann::json result = {
        {"bench", "render"},
        {"mode", motion},
        {"input", o.input},
        {"points", o.points},
        {"points_drawn", look.stats.points_drawn},
        {"width", w},
        {"height", h},
        {"frames", t.frames},
        {"frame_budget_ms", o.frame_budget_ms},
        {"degrees_per_frame", o.degrees_per_frame},
        {"renderer", o.gl_renderer},
        {"asked", rasterizerKindName(o.settings.rasterizer)},
        {"rasterizer", rasterizerLabel(look.stats.rasterizer)},
        {"atomic64", atomic64},
        {"allow_atomic64", o.compute.allow_64bit_atomics},
        {"fallback_reason", look.stats.fallback_reason},
        // Splats of the last frame drawn a workgroup each (wider than an inline splat).
        {"large_splats", large_splats},
        {"chunks_drawn", look.stats.chunks_drawn},
        {"settings", lookJson(o.look, o.settings, o.stereo)},
        {"median_ms", t.median_ms},
        {"p90_ms", t.p90_ms},
        {"worst_ms", t.worst_ms},
        {"cpu_ms", median(look.cpu) * 1e3},
        {"points_per_second",
         t.median_ms > 0 ? double(look.stats.points_drawn) / t.median_ms * 1e3 : 0.0},
        {"reference",
         {{"name", reference_name},
          {"rasterizer", "points"},
          {"median_ms", r.median_ms},
          {"p90_ms", r.p90_ms},
          {"worst_ms", r.worst_ms},
          {"cpu_ms", median(plain.cpu) * 1e3}}},
        {"ratio", ratio},
        {"load_average", {{"before", load_before}, {"after", load_after}}}};
    std::printf("%s\n", result.dump().c_str());
    return 0;
  }
  std::printf("bench render: %s, %llu points, %dx%d, %s of %d frames", o.input.c_str(),
              static_cast<unsigned long long>(o.points), w, h, motion, o.frames);
  if (o.degrees_per_frame > 0) std::printf(" (%g degrees a frame)", o.degrees_per_frame);
  std::printf(", on %s\n", o.gl_renderer.c_str());
  std::printf("look (%s): %s\n", o.look.c_str(), lookLine(o.settings, o.stereo).c_str());
  if (refine) {
    std::printf(
        "moving frames refined within %.1f ms (the viewer's step; the last frame drew "
        "%llu of the chunks)\n",
        o.frame_budget_ms, static_cast<unsigned long long>(look.stats.chunks_drawn));
  }
  if (!look.stats.fallback_reason.empty()) {
    std::printf("compute asked, GL_POINTS drew: %s\n", look.stats.fallback_reason.c_str());
  }
  if (large_splats) {
    std::printf("%llu splats over %g pixels drawn a workgroup each in the look's last frame\n",
                static_cast<unsigned long long>(large_splats),
                double(ComputeRasterizer::kInlineSplatPx));
  }
  std::printf("%-30s %-8s %9s %9s %9s %9s %11s\n", "frame times (ms)", "drawn by", "median", "p90",
              "worst", "cpu", "M points/s");
  printRow(compute ? (atomic64 ? "look (64-bit atomics)" : "look (32-bit atomics)") : "look", look,
           t);
  printRow(("reference: " + reference_name).c_str(), plain, r);
  std::printf(
      "ratio reference / look %.2f (median; below 1: the look costs more)   points a "
      "frame %.2f M   load %.2f -> %.2f\n",
      ratio, double(look.stats.points_drawn) / 1e6, load_before[0], load_after[0]);
  return 0;
}

}  // namespace parallax::cli
