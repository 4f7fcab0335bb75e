#include "render/node_selection.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <queue>

#include "render/frustum.h"

namespace parallax {

SelectionView selectionViewFor(const View& view, const Bounds3& scene) {
  const Camera& camera = view.camera;
  SelectionView result;
  result.world_to_clip =
      camera.projectionMatrix(view.aspect(), camera.clipRange(scene)) * camera.viewMatrix();
  result.eye = camera.position;
  result.projection = camera.projection;
  result.slope = std::tan(glm::radians(camera.fov_y_deg) * 0.5);
  result.ortho_height = camera.ortho_height;
  result.viewport_height = double(view.viewport.height);
  result.pixels = view.output;
  return result;
}

namespace {

// Area of the union of the views' pixel rectangles (those given), on the grid their edges make.
std::uint64_t unionPixelArea(std::span<const SelectionView> views) {
  std::vector<int> xs, ys;
  for (const SelectionView& view : views) {
    const Viewport& r = view.pixels;
    if (r.width <= 0 || r.height <= 0) continue;
    xs.insert(xs.end(), {r.x, r.x + r.width});
    ys.insert(ys.end(), {r.y, r.y + r.height});
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  std::uint64_t area = 0;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      const bool covered = std::any_of(views.begin(), views.end(), [&](const SelectionView& v) {
        const Viewport& r = v.pixels;
        return r.width > 0 && r.height > 0 && r.x <= xs[i] && xs[i + 1] <= r.x + r.width &&
               r.y <= ys[j] && ys[j + 1] <= r.y + r.height;
      });
      if (covered) area += std::uint64_t(xs[i + 1] - xs[i]) * std::uint64_t(ys[j + 1] - ys[j]);
    }
  }
  return area;
}

}  // namespace

std::uint64_t viewsPointBudget(std::uint64_t budget, std::span<const SelectionView> views) {
  std::uint64_t largest = 0;
  for (const SelectionView& view : views) {
    if (view.pixels.width > 0 && view.pixels.height > 0)
      largest = std::max(largest, std::uint64_t(view.pixels.width) * view.pixels.height);
  }
  const std::uint64_t covered = unionPixelArea(views);
  if (largest == 0 || largest == covered) return budget;
  // budget x largest / covered, rounded down, without overflowing for a budget near the maximum.
  return budget / covered * largest + budget % covered * largest / covered;
}

double projectedRadius(const Bounds3& box, const SelectionView& view) {
  const auto size = box.size();
  const double radius = 0.5 * std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
  if (view.projection == Projection::Orthographic) {
    return radius * view.viewport_height / std::max(view.ortho_height, 1e-300);
  }
  const auto center = box.center();
  const double distance = glm::length(glm::dvec3(center[0], center[1], center[2]) - view.eye);
  // Inside the sphere the node surrounds the eye: it matters more than anything else.
  if (distance <= radius) return std::numeric_limits<double>::infinity();
  return radius * view.viewport_height / (2.0 * distance * std::max(view.slope, 1e-300));
}

NodeSelection selectNodes(std::span<const OctreeNode> nodes, std::span<const SelectionView> views,
                          const NodeSelectionSettings& settings,
                          std::span<const std::uint8_t> resident) {
  NodeSelection selection;
  if (nodes.empty() || views.empty()) return selection;
  const std::uint64_t point_budget = viewsPointBudget(settings.point_budget, views);

  std::vector<Frustum> frusta;
  frusta.reserve(views.size());
  for (const SelectionView& view : views) frusta.emplace_back(view.world_to_clip);

  // The largest projected radius over the views that see the box; a negative value: none does.
  auto weigh = [&](const Bounds3& box) {
    double weight = -1.0;
    for (std::size_t v = 0; v < views.size(); ++v) {
      if (frusta[v].intersects(box)) weight = std::max(weight, projectedRadius(box, views[v]));
    }
    return weight;
  };

  struct Candidate {
    double weight;
    std::int32_t node;
    // Max-heap on weight; among equals the lower index pops first, so the order is reproducible.
    bool operator<(const Candidate& other) const {
      return weight != other.weight ? weight < other.weight : node > other.node;
    }
  };
  std::priority_queue<Candidate> queue;
  const double root_weight = weigh(nodes[0].box);
  if (root_weight < 0.0) return selection;
  queue.push({root_weight, 0});

  while (!queue.empty()) {
    const Candidate candidate = queue.top();
    queue.pop();
    const OctreeNode& node = nodes[std::size_t(candidate.node)];
    // Potree stops at the first node that does not fit rather than looking for smaller ones
    // further down the queue: everything chosen then outranks everything left out.
    if (candidate.node != 0 && selection.point_count + node.point_count > point_budget) {
      selection.budget_reached = true;
      break;
    }
    selection.nodes.push_back(candidate.node);
    selection.weights.push_back(candidate.weight);
    selection.point_count += node.point_count;
    const std::size_t index = std::size_t(candidate.node);
    if (index >= resident.size() || resident[index] == 0)
      selection.missing.push_back(candidate.node);
    if (node.hierarchy_pending) {
      selection.expand.push_back(candidate.node);
      continue;
    }
    for (int i = 0; i < 8; ++i) {
      const std::int32_t child = node.children[std::size_t(i)];
      if (!(node.child_mask & (1u << i)) || child < 0 || std::size_t(child) >= nodes.size()) {
        continue;
      }
      const double weight = weigh(nodes[std::size_t(child)].box);
      if (weight < 0.0) {
        selection.culled.push_back(child);
      } else if (weight >= settings.min_node_size_px) {
        queue.push({weight, child});
      }
    }
  }
  return selection;
}

}  // namespace parallax
