#include "xr/frame_budget.h"

#include <algorithm>

namespace parallax {

FrameBudget::FrameBudget(const FrameBudgetSettings& settings)
    : settings_(settings), budget_(settings.most) {
  settings_.least = std::min(settings_.least, settings_.most);
}

std::uint64_t FrameBudget::update(double frame_s, double period_s, std::uint64_t points_drawn) {
  if (frame_s <= 0 || period_s <= 0) return budget_;
  const double target = period_s * settings_.headroom;
  double next = double(budget_);
  if (frame_s > target) {
    // Points cost about the same each: scale to the time there is, at most halving per frame so
    // that one slow frame (a node upload, the runtime's hiccup) does not empty the picture.
    next = double(std::min(budget_, points_drawn)) * std::max(0.5, target / frame_s);
  } else if (frame_s < period_s * settings_.grow_below && points_drawn >= budget_ * 9 / 10) {
    next = double(budget_) * 1.1;
  }
  budget_ = std::clamp(std::uint64_t(next), settings_.least, settings_.most);
  return budget_;
}

}  // namespace parallax
