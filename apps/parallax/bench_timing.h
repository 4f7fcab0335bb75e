// Timing helpers of the render benchmarks (bench_render*.cpp): process CPU time, the load
// average beside each figure, medians and percentiles.
#pragma once

#include <time.h>

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <utility>
#include <vector>

#include "render/frame_times.h"

namespace parallax::cli {

inline double processCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

// /proc/loadavg's three figures (zeros where it cannot be read).
inline std::vector<double> loadAverage() {
  std::ifstream file("/proc/loadavg");
  std::vector<double> load(3, 0.0);
  file >> load[0] >> load[1] >> load[2];
  return load;
}

inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

// The value below which `fraction` of `values` lie: 0.5 the (upper) median, 1.0 the largest. For
// one set of values, a larger fraction never gives a smaller value. 0 for no values.
// The benchmarks' percentiles are the viewer's (render/frame_times.h); 0 for no values.
inline double percentile(std::vector<double> values, double fraction) {
  return values.empty() ? 0.0 : framePercentile(std::move(values), fraction);
}

}  // namespace parallax::cli
