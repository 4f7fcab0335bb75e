// Node selection for level-of-detail rendering: which octree nodes a frame draws.
//
// As Potree does it (Schütz, "Potree: Rendering Large Point Clouds in Web Browsers", 2016, ch. 4):
// from the root, a priority queue on each node's projected size on screen; a node is taken if any
// view sees its box, and its children are queued in turn. The traversal stops at the point budget
// and skips nodes whose projected size falls below a minimum. Because a child is only queued once
// its parent is taken, every chosen node's ancestors are chosen too, and they come before it.
//
// Pure CPU and no GL, so it is unit-tested on hand-made hierarchies (tests/render/
// test_node_selection.cpp).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "core/bounds.h"
#include "lod/octree.h"
#include "render/camera.h"
#include "render/view.h"

namespace parallax {

// What node selection needs to know of one view (one eye in stereo).
struct SelectionView {
  glm::dmat4 world_to_clip{1.0};  // projection x view, depth range [0, w] (Frustum's convention)
  glm::dvec3 eye{0.0};            // camera position, world coordinates
  Projection projection = Projection::Perspective;
  double slope = 1.0;            // perspective: tan(vertical field of view / 2)
  double ortho_height = 2.0;     // orthographic: world height of the view
  double viewport_height = 1.0;  // pixels
  // The view's pixels on the output (View::output): views whose rectangles are apart share the
  // point budget (see NodeSelectionSettings::point_budget); width or height 0: not given.
  Viewport pixels{0, 0, 0, 0};
};

// The view's camera with near and far planes that hold `scene` (Camera::clipRange), its aspect
// (View::aspect(), so a squeezed side-by-side eye and an off-axis eye are what they draw).
SelectionView selectionViewFor(const View& view, const Bounds3& scene);

struct NodeSelectionSettings {
  // Points per frame over the output's pixels the frame's views cover together (the union of
  // their `pixels`): each view gets the points per pixel of one view filling them all. The views
  // see the same scene and one selection is drawn in each, so it gets point_budget x (the largest
  // view's pixels / the union's pixels): the whole budget for one view (mono) or eyes on the same
  // pixels (anaglyph, interlaced, quad buffer), half of it for eyes side by side or one above the
  // other (sbs, sbs squeezed, top-bottom), whose eyes then draw as many points per pixel as mono.
  // Views that do not state their pixels (a headset's eyes, whose budget follows the frame time)
  // get the whole budget. The root is taken even when it alone holds more (a picture of
  // something beats an empty one).
  std::uint64_t point_budget = 3'000'000;
  // Nodes whose projected radius is smaller (pixels) are skipped with their subtrees; the root
  // never is. Potree's default, 30: a node holds about 128 points across its box (the root's
  // spacing is the cube / 128 in PotreeConverter), so below 30 px its points are denser than
  // the pixels and its parent already shows what can be seen.
  double min_node_size_px = 30.0;
};

struct NodeSelection {
  // Chosen nodes, most important first (descending projected size; ties: lower index first).
  // Every node's parent comes before it.
  std::vector<std::int32_t> nodes;
  std::vector<double> weights;    // projected radius in pixels of nodes[i] (+inf: eye inside)
  std::uint64_t point_count = 0;  // of all chosen nodes
  // Chosen nodes not marked resident, in the same order: what the loader should fetch.
  std::vector<std::int32_t> missing;
  // Chosen nodes whose hierarchy is pending (proxies), in the same order: their children are
  // unknown until Octree::expandHierarchy().
  std::vector<std::int32_t> expand;
  // Children of chosen nodes whose boxes no view sees. Their parent's points inside them are
  // off screen too, which lets the draw list treat them as covered (GpuNodeCache's sizing rule).
  std::vector<std::int32_t> culled;
  bool budget_reached = false;  // a visible node was left out for the budget
};

// Projected radius (pixels) of a sphere around `box` in one view: radius x viewport height /
// (2 x distance x slope) in perspective, +inf with the eye inside the sphere; radius x viewport
// height / ortho height in orthographic projection.
double projectedRadius(const Bounds3& box, const SelectionView& view);

// The point budget for one selection serving `views` (NodeSelectionSettings::point_budget):
// budget x the largest view's pixel area / the area of the union of their pixel rectangles,
// rounded down. The budget itself when no view gives its pixels.
std::uint64_t viewsPointBudget(std::uint64_t budget, std::span<const SelectionView> views);

// Selects nodes of `nodes` (node 0 the root) for `views`. A node counts as visible if any view's
// frustum meets its box; its weight is the largest projected radius over the views that see it.
// `resident[i]` != 0 marks node i as ready to draw (shorter spans: the rest are not resident).
NodeSelection selectNodes(std::span<const OctreeNode> nodes, std::span<const SelectionView> views,
                          const NodeSelectionSettings& settings,
                          std::span<const std::uint8_t> resident = {});

}  // namespace parallax
