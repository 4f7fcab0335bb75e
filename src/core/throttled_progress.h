// A Progress that reports at most every 1/200 of its total (every 2^20 units when the total is
// unknown), one report at a time, from whichever thread advances it: for observers that are
// costly to call (a Python callable, a host's callback), unlike the terminal's bar.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>

#include "core/progress.h"

namespace parallax {

class ThrottledProgress : public Progress {
 public:
  explicit ThrottledProgress(std::uint64_t total)
      : total_(total),
        step_(total ? std::max<std::uint64_t>(1, total / 200) : (1u << 20)),
        next_(step_) {}

  void advance(std::uint64_t amount) final {
    const std::uint64_t done = done_.fetch_add(amount) + amount;
    if (done < next_.load()) return;
    const std::lock_guard lock(report_mutex_);
    if (done < next_.load()) return;
    next_ = done + step_;
    report(done);
  }

  std::uint64_t done() const { return done_.load(); }
  std::uint64_t total() const { return total_; }

 protected:
  // Called with report_mutex_ held.
  virtual void report(std::uint64_t done) = 0;
  // Held by every report; a final report outside advance() takes it too.
  std::mutex report_mutex_;

 private:
  const std::uint64_t total_;
  const std::uint64_t step_;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<std::uint64_t> next_;
};

}  // namespace parallax
