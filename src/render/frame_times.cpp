#include "render/frame_times.h"

#include <algorithm>
#include <cassert>

namespace parallax {

double framePercentile(std::vector<double> values, double fraction) {
  assert(!values.empty() && "framePercentile of no values");
  std::sort(values.begin(), values.end());
  const auto at = std::size_t(std::max(0.0, fraction) * double(values.size()));
  return values[std::min(values.size() - 1, at)];
}

FrameTimes::FrameTimes(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {
  times_.reserve(capacity_);
}

void FrameTimes::add(double seconds) {
  if (times_.size() < capacity_) {
    times_.push_back(seconds);
    return;
  }
  times_[next_] = seconds;
  next_ = (next_ + 1) % capacity_;
}

FrameTimeSummary FrameTimes::summary() const {
  if (times_.empty()) return {};
  return {times_.size(), framePercentile(times_, 0.5), framePercentile(times_, 0.9),
          framePercentile(times_, 1.0)};
}

}  // namespace parallax
