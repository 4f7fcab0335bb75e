// `parallax bench render DIR --budget N` (bench_render_lod.cpp): frame time of level-of-detail
// rendering on a Potree directory beside the same points drawn plainly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/stereo.h"

namespace parallax::cli {

struct LodRenderBenchOptions {
  std::string directory;
  std::uint64_t budget = 3'000'000;
  double min_node_size = 30.0;  // pixels (NodeSelectionSettings)
  int width = 1920, height = 1080;
  int repeat = 5;
  std::vector<StereoMode> stereo;  // measured after mono
};

int runBenchRenderLod(const LodRenderBenchOptions& options);

}  // namespace parallax::cli
