#include "render/progressive.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "render/frustum.h"

namespace parallax {

DrawSet prioritizedDrawSet(const DrawSet& draw_set, std::span<const View> views) {
  std::vector<Frustum> frusta;
  frusta.reserve(views.size());
  for (const View& view : views) {
    const Camera& camera = view.camera;
    frusta.emplace_back(camera.projectionMatrix(view.aspect(), camera.clipRange(draw_set.bounds)) *
                        camera.viewMatrix());
  }
  std::vector<std::pair<double, std::size_t>> order;  // (priority, index)
  order.reserve(draw_set.items.size());
  for (std::size_t i = 0; i < draw_set.items.size(); ++i) {
    const Bounds3& box = draw_set.items[i].chunk->bounds;
    double priority = -1.0;  // outside every frustum
    for (std::size_t v = 0; v < views.size(); ++v) {
      if (!frusta[v].intersects(box)) continue;
      const glm::dvec3 eye = views[v].camera.position;
      const glm::dvec3 low(box.min[0], box.min[1], box.min[2]);
      const glm::dvec3 high(box.max[0], box.max[1], box.max[2]);
      const double distance = glm::length(glm::clamp(eye, low, high) - eye);
      const double size = glm::length(high - low);
      priority = std::max(priority,
                          distance > 0 ? size / distance : std::numeric_limits<double>::infinity());
    }
    order.emplace_back(priority, i);
  }
  // Stable on the index: equal priorities keep the file's order.
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  DrawSet sorted = draw_set;
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted.items[i] = draw_set.items[order[i].second];
  }
  return sorted;
}

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
