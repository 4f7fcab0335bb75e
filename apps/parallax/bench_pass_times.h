// The compute rasterizer's passes timed apart (`--pass-times` of bench xr and bench render):
// ComputeRasterizerOptions::time_passes puts a glFinish after the clears and after each pass.
#pragma once

#include <cstdio>
#include <vector>

#include "bench_timing.h"
#include "render/compute_rasterizer.h"

namespace parallax::cli {

// The medians of the compute rasterizer's passes timed apart (--pass-times).
inline void printPassTimes(const char* what, const std::vector<ComputePassTimes>& frames) {
  const auto of = [&](double ComputePassTimes::*field) {
    std::vector<double> values;
    for (const ComputePassTimes& t : frames) values.push_back(t.*field);
    return median(values);
  };
  std::printf(
      "  %s, passes (wall / CPU ms, medians): clears and setup %.1f / %.1f, pass 1 %.1f / %.1f, "
      "pass 2 "
      "%.1f / %.1f, resolve %.1f / %.1f\n",
      what, of(&ComputePassTimes::clear_ms), of(&ComputePassTimes::clear_cpu_ms),
      of(&ComputePassTimes::pass1_ms), of(&ComputePassTimes::pass1_cpu_ms),
      of(&ComputePassTimes::pass2_ms), of(&ComputePassTimes::pass2_cpu_ms),
      of(&ComputePassTimes::resolve_ms), of(&ComputePassTimes::resolve_cpu_ms));
}

}  // namespace parallax::cli
