// Timing helpers of the benchmarks (bench_render*.cpp, command_bench*.cpp) and of render's
// phase times: wall and CPU time, the load average beside each figure, medians and percentiles.
#pragma once

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <fstream>
#include <utility>
#include <vector>

#include "core/column.h"
#include "render/frame_times.h"

namespace parallax::cli {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

inline double processCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

// User + system CPU seconds so far of this process (RUSAGE_SELF) or of its finished children
// (RUSAGE_CHILDREN: the peers a benchmark runs): on a shared machine the work per core is better
// measured by CPU time than by wall time divided by the cores.
inline double rusageCpuSeconds(int who) {
  rusage usage{};
  getrusage(who, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Touches `bytes` of memory allocated as columns are (core/column.h) and frees it, so that the
// timed action that follows allocates memory just freed. These virtual machines' balloon driver
// hands memory freed for about 2 s back to the host (free page reporting), and the next first touch
// of it costs about 4 ms a MB where memory just freed costs about 0.2: without this, whichever
// action allocated first after a pause would pay for it (scripts/bench_python.py does the same).
inline void touchAndFreeMemory(std::size_t bytes) {
  ByteBuffer memory(bytes);
  constexpr std::size_t kPage = 4096;
  // volatile: stores to memory freed right after are otherwise dead to the optimiser
  volatile std::byte* pages = memory.data();
  for (std::size_t at = 0; at < bytes; at += kPage) pages[at] = std::byte{1};
}

// This process's peak resident memory so far in MB (ru_maxrss: kilobytes on Linux).
inline double peakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
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
