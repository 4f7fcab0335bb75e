// The level-of-detail front for the frame loop: one octree, streamed to the GPU as the views
// need it. Each update() selects nodes for the frame's views, asks the background loader for
// what is missing, uploads what has arrived within a per-frame budget, evicts what the cache has
// no room for, and returns the DrawSet to draw. It never waits on the disk or the network:
// nodes not loaded yet are simply not drawn (their parents are, at a coarser density), and a
// proxy whose hierarchy chunk is not in memory (Octree::hierarchyReady) is fetched by the
// loader and expanded in a later update.
//
// What is drawn: the selected nodes that are resident and whose parent is drawn (Potree's rule;
// with additive LOD a child without its parent is a sparse, misleading picture), in selection
// order (most important first).
//
// Point size (DrawItem::node_spacing): a node's points are sized by the finest density that
// covers the node's whole box. With additive LOD, where a node's child is drawn too, the points of
// both together are spaced like the child's; where a child is missing, only the node's own
// spacing holds. So a node gets max over its children of their effective spacing when every
// child is drawn or culled (a child outside every frustum hides nothing on screen), and its own
// spacing otherwise. This is a per-node stand-in for Potree's per-point "deepest visible level
// here" (which needs a visibility texture): where children are only partly drawn the node's
// points keep their larger size, which leaves no holes and blurs detail a little.
//
// One thread: update() and everything else belong to the thread that owns the GL context.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lod/octree.h"
#include "render/draw_set.h"
#include "render/gpu_node_cache.h"
#include "render/node_loader.h"
#include "render/node_selection.h"
#include "render/view.h"

namespace parallax {

// Fixed for a scene's life.
struct LodSceneOptions {
  // GPU memory for node buffers. About 28 bytes a point with colours and normals, so 512 MiB is
  // some 19 M points: six times the default point budget, room to turn around without reloading.
  std::uint64_t gpu_budget_bytes = 512ull << 20;
  int loader_threads = 2;
};

// May change every frame (the viewer's budget slider).
struct LodFrameSettings {
  NodeSelectionSettings selection;
  // Points uploaded per update (at least one node): about 28 MB of buffers, a few ms on a GPU
  // and some 10 ms of copying on llvmpipe, so a frame never stalls on uploads.
  std::uint64_t upload_points_per_frame = 1'000'000;
  // Proxy nodes whose hierarchy chunk is read per update (a small read each).
  int hierarchy_expansions_per_frame = 4;
};

struct LodStats {
  std::size_t selected_nodes = 0;
  std::uint64_t selected_points = 0;
  std::size_t drawn_nodes = 0;
  std::uint64_t drawn_points = 0;
  std::size_t resident_nodes = 0;
  std::uint64_t gpu_bytes = 0;
  std::size_t pending_loads = 0;   // queued or in flight in the loader, or loaded, not uploaded
  std::size_t uploaded_nodes = 0;  // this update
  std::uint64_t uploaded_points = 0;
  std::uint64_t evictions = 0;   // since the scene was made
  std::size_t failed_nodes = 0;  // nodes whose load or hierarchy read failed (not retried)
  bool budget_reached = false;
  bool gpu_full = false;  // a selected node did not fit in the GPU budget this update
};

class LodScene {
 public:
  // `octree` must outlive the scene; needs a current GL context for its whole life.
  explicit LodScene(Octree& octree, const LodSceneOptions& options = {});

  // One frame's work (see the file comment). The DrawSet and its chunk pointers stay valid until
  // the next update() or the scene's end.
  const DrawSet& update(std::span<const View> views, const LodFrameSettings& settings = {});
  const DrawSet& update(std::span<const SelectionView> views, const LodFrameSettings& settings);

  // True when the last update drew every node it selected (nodes that failed to load count as
  // done) and no hierarchy is left to read for it: a still camera will see nothing new.
  bool complete() const { return complete_; }
  // The draw set the last update() or finishLoading() returned.
  const DrawSet& drawSet() const { return draw_set_; }
  // Updates until complete(), or until no progress is possible (the selection does not fit the
  // GPU budget), or `timeout` passes; waits for the loader in between. For `parallax render DIR`,
  // which wants the finished picture; never for the interactive frame loop.
  const DrawSet& finishLoading(std::span<const View> views, const LodFrameSettings& settings,
                               std::chrono::milliseconds timeout = std::chrono::minutes(10));

  // Ends the background loading for good (NodeLoader::stop): the octree is no longer read for
  // this scene, and drawSet() stays valid, as it was, for as long as the scene lives. For the
  // viewer, which keeps drawing a scene's last picture while a scene with other attributes
  // (Octree::selectAttributes) loads; update() must not be called afterwards.
  void stopLoading();

  const LodStats& stats() const { return stats_; }
  // The first load or hierarchy error, empty if none (the rest go to stats().failed_nodes).
  const std::string& firstError() const { return first_error_; }
  const Octree& octree() const { return octree_; }

 private:
  NodeSelection select(std::span<const SelectionView> views, const NodeSelectionSettings& settings);
  void buildDrawSet(const NodeSelection& selection);

  Octree& octree_;
  GpuNodeCache cache_;
  NodeLoader loader_;
  std::uint64_t frame_ = 0;
  // Loaded and staged on the CPU, waiting for their upload; by node.
  std::unordered_map<std::int32_t, StagedChunk> staged_;
  std::vector<std::uint8_t> failed_;            // by node: its points failed to load
  std::vector<std::uint8_t> hierarchy_failed_;  // by node: its hierarchy chunk failed to read
  std::vector<std::uint8_t> resident_;          // by node, refreshed each update
  DrawSet draw_set_;
  LodStats stats_;
  std::string first_error_;
  bool complete_ = false;
};

}  // namespace parallax
