#include "render/lod_scene.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "core/point_filter.h"

namespace parallax {

LodScene::LodScene(Octree& octree, const LodSceneOptions& options)
    : octree_(octree), cache_(options.gpu_budget_bytes), loader_(octree, options.loader_threads) {
  const OctreeInfo& info = octree.info();
  draw_set_.bounds = info.bounds.empty() ? info.cube : info.bounds;
  draw_set_.has_colors = info.has_colors, draw_set_.has_normals = info.has_normals;
  draw_set_.has_intensity = info.has_intensity;
  draw_set_.has_classification = info.has_classification;
  draw_set_.has_gps_time = std::find(info.attributes.begin(), info.attributes.end(),
                                     filter_names::kGpsTime) != info.attributes.end();
}

const DrawSet& LodScene::update(std::span<const View> views, const LodFrameSettings& settings) {
  std::vector<SelectionView> selection_views;
  for (const View& view : views)
    selection_views.push_back(selectionViewFor(view, draw_set_.bounds));
  return update(std::span<const SelectionView>(selection_views), settings);
}

void LodScene::stopLoading() {
  loader_.stop();
  staged_.clear();
}

NodeSelection LodScene::select(std::span<const SelectionView> views,
                               const NodeSelectionSettings& settings) {
  const std::size_t node_count = octree_.nodes().size();
  resident_.assign(node_count, 0);
  for (std::int32_t node : cache_.residentNodes()) resident_[std::size_t(node)] = 1;
  failed_.resize(node_count, 0);
  hierarchy_failed_.resize(node_count, 0);
  return selectNodes(octree_.nodes(), views, settings, resident_);
}

const DrawSet& LodScene::update(std::span<const SelectionView> views,
                                const LodFrameSettings& settings) {
  ++frame_;
  if (const auto intensity = loader_.intensityLayout()) {
    draw_set_.intensity_min = intensity->min, draw_set_.intensity_max = intensity->max;
    draw_set_.intensity_integral = intensity->integral;
  }
  stats_.uploaded_nodes = 0, stats_.uploaded_points = 0, stats_.gpu_full = false;

  auto fail = [&](std::vector<std::uint8_t>& failed, std::int32_t node,
                  const std::string& message) {
    if (failed.size() <= std::size_t(node)) failed.resize(std::size_t(node) + 1, 0);
    if (!failed[std::size_t(node)]) ++stats_.failed_nodes;
    failed[std::size_t(node)] = 1;
    if (first_error_.empty()) first_error_ = message;
  };
  for (LoadedNode& loaded : loader_.takeLoaded()) {
    if (loaded.hierarchy) {
      // A chunk fetched (expanded below, once the selection reaches it again) or failed.
      if (!loaded.error.empty()) fail(hierarchy_failed_, loaded.node, loaded.error);
    } else if (!loaded.error.empty()) {
      fail(failed_, loaded.node, loaded.error);
    } else if (!cache_.contains(loaded.node)) {
      staged_[loaded.node] = std::move(loaded.staged);
    }
  }

  // Proxies first: reading a hierarchy chunk is small, and the selection can only go below a
  // proxy once it is read. At most a few per frame, then select again with what was read.
  NodeSelection selection = select(views, settings.selection);
  int expansions = 0;
  while (!selection.expand.empty() && expansions < settings.hierarchy_expansions_per_frame) {
    bool expanded = false;
    for (std::int32_t node : selection.expand) {
      if (expansions >= settings.hierarchy_expansions_per_frame) break;
      // Not in memory yet (a URL): the loader fetches it; the frame loop never waits for it.
      if (hierarchy_failed_[std::size_t(node)] || !octree_.hierarchyReady(node)) continue;
      ++expansions;
      try {
        octree_.expandHierarchy(node);
        expanded = true;
      } catch (const std::exception& error) {
        // The node's own points may still be fine: it is drawn, only never refined.
        fail(hierarchy_failed_, node, error.what());
      }
    }
    if (!expanded) break;
    selection = select(views, settings.selection);
  }

  // Uploads, most important first, within the frame's budget (at least one node, so a node
  // larger than the budget still arrives). Only under a resident parent: a node is drawn only
  // under a drawn parent, so GPU memory never goes to a node that cannot be drawn yet. Nodes are
  // still read in parallel with their parents (the loader has them all), which fills the
  // first frames faster than Potree's parent-then-children reading.
  const std::span<const OctreeNode> nodes = octree_.nodes();
  // Nodes under a node that failed to load can never be drawn: neither loaded nor waited for.
  std::vector<std::uint8_t> blocked(nodes.size(), 0);
  for (std::int32_t node : selection.nodes) {
    cache_.touch(node, frame_);
    const std::int32_t parent = nodes[std::size_t(node)].parent;
    blocked[std::size_t(node)] =
        failed_[std::size_t(node)] || (parent >= 0 && blocked[std::size_t(parent)]);
  }
  for (std::int32_t node : selection.missing) {
    const auto staged = staged_.find(node);
    if (staged == staged_.end() || blocked[std::size_t(node)]) continue;
    const std::int32_t parent = nodes[std::size_t(node)].parent;
    if (parent >= 0 && !resident_[std::size_t(parent)]) continue;
    if (stats_.uploaded_nodes > 0 &&
        stats_.uploaded_points + staged->second.chunk.count > settings.upload_points_per_frame) {
      break;
    }
    if (!cache_.insert(node, nodes[std::size_t(node)].level, staged->second, frame_)) {
      stats_.gpu_full = true;
      break;
    }
    ++stats_.uploaded_nodes, stats_.uploaded_points += staged->second.chunk.count;
    resident_[std::size_t(node)] = 1;
    staged_.erase(staged);
  }
  cache_.trim(frame_);

  // Staged nodes the frame no longer wants are dropped: CPU memory stays bounded by what one
  // selection needs, at the price of reading a node again if the camera turns back.
  std::unordered_set<std::int32_t> wanted;
  std::vector<std::int32_t> to_load;
  for (std::int32_t node : selection.missing) {
    if (resident_[std::size_t(node)] || blocked[std::size_t(node)]) continue;
    wanted.insert(node);
    if (!staged_.count(node)) to_load.push_back(node);
  }
  std::erase_if(staged_, [&](const auto& item) { return !wanted.count(item.first); });
  std::vector<std::int32_t> to_fetch;
  for (std::int32_t node : selection.expand) {
    if (!blocked[std::size_t(node)] && !hierarchy_failed_[std::size_t(node)] &&
        !octree_.hierarchyReady(node)) {
      to_fetch.push_back(node);
    }
  }
  loader_.request(nodes, to_load, to_fetch);

  buildDrawSet(selection);

  stats_.selected_nodes = selection.nodes.size();
  stats_.selected_points = selection.point_count;
  stats_.resident_nodes = cache_.size();
  stats_.gpu_bytes = cache_.bytes();
  stats_.pending_loads = loader_.pending() + staged_.size();
  stats_.evictions = cache_.evictions();
  stats_.budget_reached = selection.budget_reached;
  bool all_drawn = true;
  for (std::int32_t node : selection.nodes) {
    if (!blocked[std::size_t(node)] && !cache_.contains(node)) all_drawn = false;
  }
  bool expansions_left = false;
  for (std::int32_t node : selection.expand) {
    expansions_left |= !blocked[std::size_t(node)] && !hierarchy_failed_[std::size_t(node)];
  }
  // A failed node hides its subtree (nothing is drawn under an undrawn parent); with every
  // selected node either drawn or under a failed one the frame is as complete as it can get.
  complete_ = all_drawn && !expansions_left;
  return draw_set_;
}

void LodScene::buildDrawSet(const NodeSelection& selection) {
  const std::span<const OctreeNode> nodes = octree_.nodes();
  // Per node: 1 drawn, 2 culled by every frustum (covers nothing on screen), 0 otherwise.
  std::vector<std::uint8_t> state(nodes.size(), 0);
  for (std::int32_t node : selection.culled) state[std::size_t(node)] = 2;
  std::vector<std::int32_t> drawn;
  for (std::int32_t node : selection.nodes) {
    const OctreeNode& n = nodes[std::size_t(node)];
    if (!cache_.contains(node)) continue;
    if (n.parent >= 0 && state[std::size_t(n.parent)] != 1) continue;
    state[std::size_t(node)] = 1;
    drawn.push_back(node);
  }

  // Effective spacing, children before parents (the reverse of the selection order).
  std::vector<double> effective(nodes.size(), 0.0);
  for (auto it = drawn.rbegin(); it != drawn.rend(); ++it) {
    const OctreeNode& n = nodes[std::size_t(*it)];
    double finest_cover = 0.0;
    bool covered = n.child_mask != 0 && !n.hierarchy_pending;
    for (int i = 0; i < 8 && covered; ++i) {
      if (!(n.child_mask & (1u << i))) continue;
      const std::int32_t child = n.children[std::size_t(i)];
      if (child < 0) {
        covered = false;
      } else if (state[std::size_t(child)] == 1) {
        finest_cover = std::max(finest_cover, effective[std::size_t(child)]);
      } else if (state[std::size_t(child)] != 2) {
        covered = false;
      }
    }
    // A node whose children are all culled is off screen but for its own box's visible part,
    // which no child covers: it keeps its own spacing.
    effective[std::size_t(*it)] = covered && finest_cover > 0.0 ? finest_cover : n.spacing;
  }

  draw_set_.items.clear();
  stats_.drawn_points = 0;
  int deepest = 0;
  for (std::int32_t node : drawn) {
    const PointChunk* chunk = cache_.find(node);
    const OctreeNode& n = nodes[std::size_t(node)];
    draw_set_.items.push_back({chunk, float(effective[std::size_t(node)]), n.level, node});
    stats_.drawn_points += chunk->count;
    deepest = std::max(deepest, n.level);
  }
  stats_.drawn_nodes = drawn.size();
  // The density of the finest level drawn: what a whole-cloud upload would call typical.
  const double root_spacing = octree_.info().spacing > 0 ? octree_.info().spacing
                                                         : (nodes.empty() ? 0.0 : nodes[0].spacing);
  draw_set_.typical_spacing = root_spacing / std::ldexp(1.0, deepest);
}

const DrawSet& LodScene::finishLoading(std::span<const View> views,
                                       const LodFrameSettings& settings,
                                       std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    update(views, settings);
    if (complete_ || stats_.gpu_full || std::chrono::steady_clock::now() >= deadline) break;
    // Nothing owed by the loader or waiting for upload, yet incomplete: no update can change
    // that (a guard; every incomplete case above should leave work pending).
    if (stats_.uploaded_nodes == 0 && stats_.pending_loads == 0) break;
    // Nothing staged and nothing to upload: wait for the loader rather than spin.
    if (stats_.uploaded_nodes == 0) loader_.waitForLoaded(std::chrono::milliseconds(50));
  }
  return draw_set_;
}

}  // namespace parallax
