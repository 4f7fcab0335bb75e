#include "io/read_ahead.h"

#include <algorithm>
#include <cassert>

namespace parallax {

ReadAhead::ReadAhead(const ByteSource& in, std::vector<ByteRange> plan, std::size_t window)
    : in_(in),
      plan_(std::move(plan)),
      window_(std::max<std::size_t>(window, 1)),
      active_(!in.local() && plan_.size() > 1),
      done_(plan_.size(), false) {
  if (!active_) return;
  const std::lock_guard lock(mutex_);
  hint();
}

void ReadAhead::finished(std::size_t index) {
  assert(index < plan_.size() && "ReadAhead::finished: an index outside the plan");
  if (!active_) return;
  const std::lock_guard lock(mutex_);
  done_[index] = true;
  while (first_open_ < plan_.size() && done_[first_open_]) ++first_open_;
  hint();
}

void ReadAhead::hint() {
  // The ranges being read stay in the hint (the first unfinished ones): a hint that left out a
  // range in flight could cancel its request before the read that wants it waits for it.
  if (hinted_from_ == first_open_) return;
  hinted_from_ = first_open_;
  std::vector<ByteRange> ranges;
  for (std::size_t i = first_open_; i < plan_.size() && ranges.size() < window_; ++i) {
    if (!done_[i]) ranges.push_back(plan_[i]);
  }
  in_.prefetch(ranges);
}

}  // namespace parallax
