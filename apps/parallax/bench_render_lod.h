// `parallax bench render DIR --budget N` (bench_render_lod.cpp): frame time of level-of-detail
// rendering on a Potree directory beside the same points drawn plainly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lod/octree.h"
#include "render/camera.h"
#include "render/compute_rasterizer.h"
#include "render/render_settings.h"
#include "render/stereo.h"

namespace parallax::cli {

struct LodRenderBenchOptions {
  std::string directory;  // for the report (the octree is opened by the caller)
  std::uint64_t budget = 3'000'000;
  double min_node_size = 30.0;  // pixels (NodeSelectionSettings)
  int width = 1920, height = 1080;
  int repeat = 5;
  std::vector<StereoMode> stereo;  // measured after mono
  RenderSettings settings;         // the rasterizer among them
  // > 0: instead, an orbit of this many frames around the cloud with streaming, as the viewer
  // draws it (LodScene::update every frame, no waiting), and progressive refinement within
  // frame_budget_ms per moving frame when that is > 0.
  int orbit_frames = 0;
  double frame_budget_ms = 0;
  StereoSettings orbit_stereo;       // the orbit's views (mono unless --stereo MODE)
  Camera camera;                     // the first view (render's and the viewer's default camera)
  std::string look = "render";       // where `settings` came from, for the report
  ComputeRasterizerOptions compute;  // allow_64bit_atomics false: --no-atomic64
  bool json = false;  // the orbit as one JSON object on stdout (median_ms, p90_ms, worst_ms, ...)
  // Instead: the load timed with the nodes read with what `settings` draws (attributesDrawn, as
  // the viewer reads them; COPC decodes only those layers) and with every attribute, `repeat`
  // rounds of each, alternating (the first of each a warm-up: hierarchy pages, disk cache).
  bool selective_load = false;
};

int runBenchRenderLod(const LodRenderBenchOptions& options, Octree& octree);

}  // namespace parallax::cli
