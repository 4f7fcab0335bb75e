// `parallax bench render FILE [--orbit N]` (bench_render_orbit.cpp): the frame times of a point
// file drawn whole, with the look people see (`--look viewer`, or any look option of `view`),
// while the camera orbits, beside a same-run reference; and what the orbits of a file and of an
// octree (bench_render_lod.cpp) share: the camera's step, the frame-time summary and the look as
// JSON.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include "render/camera.h"
#include "render/compute_rasterizer.h"
#include "render/draw_set.h"
#include "render/render_settings.h"
#include "render/stereo.h"

namespace parallax::cli {

// The camera turns this much a frame around its pivot (turntable, around world_up): what a
// user's drag does to the viewer at about 60 pixels a second.
inline constexpr double kOrbitDegreesPerFrame = 2.0;

// One frame's step of every orbit.
void orbitStep(Camera& camera);

// Median, 90th percentile and worst of frame times (milliseconds; median <= p90 <= worst).
struct FrameTimeSummary {
  int frames = 0;
  double median_ms = 0, p90_ms = 0, worst_ms = 0;
};
FrameTimeSummary summarizeFrames(const std::vector<double>& seconds);

// The look's settings as JSON (size mode and sizes, shape, lighting, EDL, colour, multisampling,
// hq, whether a filter is set, the stereo mode) with `look` naming where it came from
// ("render": the options as `render` reads them; "viewer": the viewer's choice on top).
nlohmann::json lookJson(const std::string& look, const RenderSettings& settings,
                        const StereoSettings& stereo);
// The same in a line for people: "size adaptive x1.5, round, lit, rgb, no EDL, mono".
std::string lookLine(const RenderSettings& settings, const StereoSettings& stereo);

struct FileOrbitBenchOptions {
  std::string input;         // for the report
  std::uint64_t points = 0;  // in the file
  int frames = 40;
  double degrees_per_frame = kOrbitDegreesPerFrame;  // 0: a still camera
  int width = 1280, height = 720;
  std::string look = "render";
  RenderSettings settings;
  StereoSettings stereo;
  ComputeRasterizerOptions compute;  // allow_64bit_atomics false: --no-atomic64
  bool json = false;
  std::string gl_renderer;  // GL_RENDERER, for the report
  // > 0: the look's frames are the viewer's (render/frame_step.h): the chunks ordered by
  // prioritizedDrawSet and drawn a part within this budget a frame by progressive refinement,
  // the camera moving every frame (the reference still draws the whole cloud).
  double frame_budget_ms = 0;
};

// Draws `draw_set` (a whole cloud) `frames` times from `camera` turning, each frame timed to
// glFinish, interleaved frame by frame with a reference taking turns to go first, so that a change
// in the machine's load hits both alike. The reference is the same look drawn by GL_POINTS where
// the compute rasterizer drew, else render's default look (1-pixel square points, unlit) with
// GL_POINTS: what the look costs. Prints a table, or with `json` one JSON object (median_ms,
// p90_ms, worst_ms, the reference, ratio = reference / look).
int runBenchRenderFileOrbit(const FileOrbitBenchOptions& options, const DrawSet& draw_set,
                            Camera camera);

}  // namespace parallax::cli
