// `parallax bench xr INPUT`: what a headset frame of `view --xr` costs the renderer (issue 24's
// figure): both eyes at a headset's resolution (2 x 1440x1600 by default, drawn as view --xr
// draws them: one draw set, one render() call, eyes side by side) against the same scene as
// mono at one eye's size, alternated frame by frame in the same run so that the machine's load
// weighs on both alike. The eyes are a head at render's default camera (the cloud from the
// south-west), 64 mm apart, with a real headset's asymmetric fields of view; the look is view's
// (xr_view.cpp). No runtime: its compositor is not the renderer's cost.
#include <epoxy/gl.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_pass_times.h"
#include "bench_timing.h"
#include "commands.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "render_options.h"
#include "render_scene.h"
#include "xr/stage_mapping.h"
#include "xr_view.h"

namespace parallax::cli {
namespace {

struct BenchXrOptions {
  std::string input;
  int eye_width = 1440, eye_height = 1600;
  int frames = 10;
  bool pass_times = false;  // the compute rasterizer's passes timed apart (glFinish between)
  bool walk = false;        // --walk: the head where view --xr stands at true scale
  RenderOptions render;
  LodOptions lod;
};

// One frame's views as view --xr makes them, and the canvas rows they need.
struct EyeFrame {
  std::vector<View> views;
  int width = 0, rows = 0;
};

EyeFrame eyeFrame(const Camera& head, int eyes, int width, int height) {
  // An Index-like headset: each eye wider on its outer side.
  const EyeFov fovs[2] = {{-0.96, 0.78, 0.96, -0.96}, {-0.78, 0.96, 0.96, -0.96}};
  const StagePlacement placement;  // the file's coordinates as the stage's, rotated to y-up
  // The head's orientation in the stage: the camera's, turned from file (z-up) to stage (y-up).
  const glm::dquat to_stage = glm::inverse(stageToFileRotation(placement));
  EyeFrame frame;
  frame.width = eyes * width;
  for (int e = 0; e < eyes; ++e) {
    StagePose pose;
    const double side = eyes == 1 ? 0.0 : (e == 0 ? -0.032 : 0.032);
    pose.position = fileToStage(placement, head.position + head.right() * side);
    pose.orientation = to_stage * head.orientation;
    const EyeView eye = eyeView(placement, fovs[e], pose, e * width, width, height);
    frame.views.push_back(eye.view);
    frame.rows = std::max(frame.rows, eye.view.viewport.height);
  }
  return frame;
}

int runBenchXr(const BenchXrOptions& o, const CLI::App& command) {
  RenderSource source = openRenderSource({.input = o.input, .command = "bench xr"}, o.lod);
  auto context = GlContext::createHeadless();
  RenderScene scene = uploadRenderSource(source, false);
  Camera head = cameraFrom(o.render, scene.extent, double(o.eye_width) / o.eye_height);
  if (o.walk) {
    // view --xr's default placement (the centre of the cloud's base at the stage's origin, true
    // scale) with the head 1.6 m up at the stage's origin, looking along the stage's -z: file +y.
    const glm::dvec3 eye = baseCentre(scene.extent.bounds) + glm::dvec3(0, 0, 1.6);
    head.lookAt(eye, eye + glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
  }
  const EyeFrame stereo = eyeFrame(head, 2, o.eye_width, o.eye_height);
  const EyeFrame mono = eyeFrame(head, 1, o.eye_width, o.eye_height);
  // A renderer for each canvas, as view --xr keeps one canvas size for the session: one
  // renderer alternating between the two sizes would reallocate (and the driver zero) its
  // framebuffer and the compute rasterizer's visibility buffer every frame, which cost more
  // than both eyes' points on llvmpipe and is nothing a headset frame pays.
  const ComputeRasterizerOptions compute{.time_passes = o.pass_times};
  Renderer stereo_renderer(compute), mono_renderer(compute);
  RenderTarget stereo_canvas(stereo.width, stereo.rows), mono_canvas(mono.width, mono.rows);
  const auto drawSetFor = [&](const EyeFrame& frame) -> const DrawSet& {
    StereoFrame views;
    views.views = frame.views;
    return frameDrawSet(scene, source, views, o.lod);
  };
  const DrawSet& first = drawSetFor(stereo);
  const RenderSettings asked = renderSettingsFrom(o.render, first.typical_spacing);
  const LookTraits traits = source.lod()
                                ? LookTraits{.spacing_known = source.octree->info().spacing > 0,
                                             .has_normals = source.octree->info().has_normals}
                                : LookTraits{.spacing_known = scene.gpu->typicalSpacing() > 0,
                                             .has_normals = scene.gpu->hasNormals()};
  const RenderSettings settings = viewerLook(asked, asked, viewerLookChoiceFrom(command), traits);
  const auto timeFrame = [&](const EyeFrame& frame, Renderer& renderer, RenderTarget& canvas,
                             FrameStats& stats) {
    const DrawSet& draw_set = drawSetFor(frame);
    const auto start = std::chrono::steady_clock::now();
    stats = renderer.render(draw_set, frame.views, settings, canvas.framebuffer(), frame.width,
                            frame.rows);
    glFinish();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
  };
  FrameStats stereo_stats, mono_stats;
  timeFrame(stereo, stereo_renderer, stereo_canvas,
            stereo_stats);  // warm-up: shaders, first uploads
  timeFrame(mono, mono_renderer, mono_canvas, mono_stats);
  std::vector<double> stereo_ms, mono_ms;
  std::vector<ComputePassTimes> stereo_passes, mono_passes;
  const std::vector<double> load_before = loadAverage();
  for (int f = 0; f < o.frames; ++f) {
    stereo_ms.push_back(timeFrame(stereo, stereo_renderer, stereo_canvas, stereo_stats));
    if (o.pass_times && stereo_stats.rasterizer == RasterizerKind::Compute) {
      stereo_passes.push_back(stereo_renderer.computeRasterizer().passTimesOfLastFrame());
    }
    mono_ms.push_back(timeFrame(mono, mono_renderer, mono_canvas, mono_stats));
    if (o.pass_times && mono_stats.rasterizer == RasterizerKind::Compute) {
      mono_passes.push_back(mono_renderer.computeRasterizer().passTimesOfLastFrame());
    }
  }
  const std::vector<double> load_after = loadAverage();
  const double s = median(stereo_ms), m = median(mono_ms);
  std::printf(
      "bench xr %s: %llu points drawn, rasterizer %s\n"
      "  both eyes, 2 x %dx%d (canvas %dx%d): median %.1f ms/frame (%.1f M points/s)\n"
      "  mono, one eye %dx%d (canvas %dx%d):   median %.1f ms/frame\n"
      "  stereo / mono: %.2fx (same run, %d frames each, alternated); load %.2f before, %.2f "
      "after\n",
      o.input.c_str(), static_cast<unsigned long long>(stereo_stats.points_drawn),
      stereo_stats.rasterizer == RasterizerKind::Compute ? "compute" : "points", o.eye_width,
      o.eye_height, stereo.width, stereo.rows, s, double(stereo_stats.points_drawn) / s / 1e3,
      o.eye_width, o.eye_height, mono.width, mono.rows, m, m > 0 ? s / m : 0.0, o.frames,
      load_before[0], load_after[0]);
  if (!stereo_passes.empty()) printPassTimes("both eyes", stereo_passes);
  if (!mono_passes.empty()) printPassTimes("mono", mono_passes);
  return 0;
}

}  // namespace

Command addBenchXrCommand(CLI::App& bench) {
  auto options = std::make_shared<BenchXrOptions>();
  Command command;
  CLI::App* sub = bench.add_subcommand(
      "xr", "A headset frame of view --xr (both eyes) beside mono at one eye's size");
  sub->add_option("input", options->input, "Point file, Potree directory or COPC file")->required();
  sub->add_option("--eye-width", options->eye_width, "One eye's width")->capture_default_str();
  sub->add_option("--eye-height", options->eye_height, "One eye's height")->capture_default_str();
  sub->add_option("--frames", options->frames, "Frames timed of each")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  sub->add_flag("--walk", options->walk,
                "The head where view --xr stands by default: 1.6 m above the centre of the "
                "cloud's base, looking north (file +y), at true scale; default: render's camera");
  sub->add_flag("--pass-times", options->pass_times,
                "Time the compute rasterizer's passes apart (a glFinish after each)");
  addRenderOptions(*sub, options->render);
  addLodOptions(*sub, options->lod);
  command.subcommand = sub;
  command.run = [options, sub] { return runBenchXr(*options, *sub); };
  return command;
}

}  // namespace parallax::cli
