#include "render/progressive.h"

#include <algorithm>

namespace parallax {

FramePart ProgressiveRefinement::plan(const DrawSet& draw_set, bool changed) {
  const std::vector<DrawItem>& items = draw_set.items;
  // Go on only where the picture holds exactly the set's first items, as they are now (a node's
  // effective spacing changes its point size when its children arrive).
  bool same = !changed && drawn_.size() <= items.size();
  for (std::size_t i = 0; same && i < drawn_.size(); ++i) {
    same = drawn_[i].first == items[i].chunk && drawn_[i].second == items[i].node_spacing;
  }
  if (!same) drawn_.clear();
  FramePart part;
  part.first_item = drawn_.size();
  part.accumulate = !drawn_.empty();
  // Items that fit the budget at the measured rate; at least one, so that every frame advances.
  const double budget_points = points_per_second_ * settings_.frame_budget_s;
  double points = 0;
  std::size_t last = part.first_item;
  while (last < items.size() &&
         (last == part.first_item || points + items[last].chunk->count <= budget_points)) {
    points += items[last].chunk->count;
    ++last;
  }
  part.last_item = last;
  for (std::size_t i = part.first_item; i < last; ++i) {
    drawn_.emplace_back(items[i].chunk, items[i].node_spacing);
  }
  complete_ = last == items.size();
  return part;
}

void ProgressiveRefinement::record(std::uint64_t points, double seconds) {
  // Frames of a few points say little about the rate (fixed costs dominate).
  if (points < 10'000 || seconds <= 0) return;
  const double rate = double(points) / seconds;
  // A quick average: a change of load or of what is on screen shows within a few frames.
  points_per_second_ = 0.5 * points_per_second_ + 0.5 * rate;
}

}  // namespace parallax
