// The times of the recent frames of a moving camera, summarised as `parallax bench render
// --orbit` summarises its orbit (median, 90th percentile, worst), so that the viewer's panel and
// the benchmark report the same figures. Pure CPU bookkeeping: tests/render/test_frame_times.cpp.
#pragma once

#include <cstddef>
#include <vector>

namespace parallax {

struct FrameTimeSummary {
  std::size_t frames = 0;  // 0: nothing recorded (the other fields are 0)
  double median_s = 0, p90_s = 0, worst_s = 0;
};

// The value at `fraction` (0..1) of the sorted values: values[min(n - 1, floor(fraction * n))],
// the definition bench_render_lod.cpp uses (fraction 0.5 is the upper median, 1.0 the worst).
// `values` must not be empty.
double framePercentile(std::vector<double> values, double fraction);

// The last `capacity` frame times (seconds), oldest dropped first.
class FrameTimes {
 public:
  explicit FrameTimes(std::size_t capacity = 120);
  void add(double seconds);
  void clear() { times_.clear(), next_ = 0; }
  std::size_t size() const { return times_.size(); }
  FrameTimeSummary summary() const;

 private:
  std::size_t capacity_;
  std::vector<double> times_;  // a ring once full; `next_` is the oldest
  std::size_t next_ = 0;
};

}  // namespace parallax
