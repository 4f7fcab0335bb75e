// The point budget that keeps a headset's frame rate (issue 24, item 2). A headset drops or
// reprojects every frame that misses its display period, which people feel at once; fewer points
// cost detail only. So the budget follows the measured frame time: down in proportion when a
// frame takes longer than the period allows, up by a tenth while frames take well under it,
// never above the budget asked for (--budget) nor below a floor that still shows the scene.
#pragma once

#include <cstdint>

namespace parallax {

struct FrameBudgetSettings {
  std::uint64_t most = 3'000'000;  // the budget asked for: never exceeded
  std::uint64_t least = 100'000;   // never below (nor above `most`)
  double headroom = 0.8;           // the share of the period the drawing may take
  double grow_below = 0.6;         // grow while frames take less than this share of the period
};

class FrameBudget {
 public:
  explicit FrameBudget(const FrameBudgetSettings& settings);

  // After a frame of `points_drawn` points took `frame_s` seconds of a `period_s` display
  // period: the budget for the next frame. A frame that drew fewer points than the budget says
  // nothing about a larger one, so the budget grows only from what was drawn.
  std::uint64_t update(double frame_s, double period_s, std::uint64_t points_drawn);
  std::uint64_t budget() const { return budget_; }

 private:
  FrameBudgetSettings settings_;
  std::uint64_t budget_;
};

}  // namespace parallax
