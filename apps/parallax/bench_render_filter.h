// `parallax bench render --filter-toggle [--returns first ...]`: what toggling a point filter
// costs in a frame. A filter is uniforms only (render/filter_uniforms.h), so the frame after a
// toggle should take what any frame with those settings takes, and upload nothing.
#pragma once

#include <cstdint>

#include "core/point_filter.h"
#include "render/render_settings.h"

namespace parallax::cli {

struct FilterRenderBenchOptions {
  std::uint64_t points = 3'000'000;
  int width = 1920, height = 1080;
  int repeat = 5;
  RenderSettings settings;  // the rasterizer among them; the filter is `filter`
  PointFilter filter;       // keeps everything: --returns first instead
};

// Prints, per kind of frame (steady without the filter, the first with it, steady with it, the
// first without it again), the median wall and CPU time, the bytes uploaded while toggling and
// how many pixels the toggle changed; then what a pick from the frame drawn costs (the viewer
// answers a click that way, before the next frame); the load average before and after.
int runBenchRenderFilter(const FilterRenderBenchOptions& options);

}  // namespace parallax::cli
