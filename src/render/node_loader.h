// Background loading of octree nodes: worker threads read nodes (Octree::loadNode) and stage them
// for the GPU (stagePointChunk: Morton order, chunk-relative floats), so that the frame loop only
// copies ready bytes into a buffer and never waits on the disk.
//
// The frame loop hands over the nodes it wants each frame, most urgent first; the queue is
// replaced, not appended to, so a node the camera has turned away from is dropped before it is
// read. A load in flight whose node is no longer wanted is cancelled where the octree can give
// it up (a read waiting on the network: Octree::loadNodeCancellable); elsewhere it finishes and
// is delivered (the cache may still want it).
//
// For octrees behind a slow link the loader also fetches hierarchy chunks (Octree::
// fetchHierarchy, before any node: they unlock the selection below a proxy), and after each
// request() hints the octree with the next nodes of the queue (Octree::prefetch), so that the
// store fetches them together while the threads stage earlier ones.
//
// Why own threads and not TBB tasks: a load mostly waits on the disk, and a TBB worker blocked
// in read() is a core taken from the parallel loops (staging, conversion) that TBB runs. The
// staging inside a load does use TBB.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "lod/octree.h"
#include "render/point_buffers.h"

namespace parallax {

struct LoadedNode {
  std::int32_t node = -1;
  // A hierarchy fetch (request()'s `hierarchy`): nothing staged; on success the octree's
  // hierarchyReady(node) is now true.
  bool hierarchy = false;
  StagedChunk staged;  // the node's points in Morton order, ready for uploadStagedChunk()
  std::string error;   // not empty: the load failed (an InputError's message); staged is empty
};

class NodeLoader {
 public:
  // `octree` must outlive the loader. Chunks are staged with the octree's attributes (colour and
  // normal sections as info() declares them), each node's spacing as its points' spacing, and
  // intensity mapped over the root node's range: the root is a sample of the whole cloud, and one
  // range for every node keeps colours continuous across node borders.
  explicit NodeLoader(const Octree& octree, int threads = 2);
  // Drops the queue and waits for the loads in flight.
  ~NodeLoader();
  // Drops the queue, waits for the loads in flight and ends the threads: nothing reads the
  // octree for this loader afterwards (what was delivered and not taken is dropped; request()
  // then queues what no thread serves). Lets the owner change the octree's attribute selection
  // (Octree::selectAttributes, which does not synchronise with readers) while keeping what it
  // uploaded.
  void stop();
  NodeLoader(const NodeLoader&) = delete;
  NodeLoader& operator=(const NodeLoader&) = delete;

  // Replaces the queue by `hierarchy` (nodes whose hierarchy chunk to fetch, hierarchy_pending
  // set) and `wanted` (nodes to load), indices into `nodes`, most urgent first; hierarchy
  // fetches go first. Work in flight or delivered and not yet taken is not queued again; work in
  // flight that neither list names any more is cancelled (see above). `nodes` is read here only
  // (the loader keeps copies), so the caller may expand the hierarchy afterwards. Never waits
  // on the octree.
  void request(std::span<const OctreeNode> nodes, std::span<const std::int32_t> wanted,
               std::span<const std::int32_t> hierarchy = {});
  // Nodes finished since the last call, in the order they finished. Never waits for a load.
  std::vector<LoadedNode> takeLoaded();
  // Blocks until a node is ready to take, or nothing is queued or in flight, or `timeout` passes.
  // For batch rendering (`parallax render DIR`); the frame loop never calls it.
  void waitForLoaded(std::chrono::milliseconds timeout);

  std::size_t queued() const;
  std::size_t inFlight() const;
  // Queued, in flight, or delivered and not taken: the nodes the loader still owes.
  std::size_t pending() const;
  // How many times loadNode was called (tests check that dropped requests were never read).
  std::uint64_t loadsStarted() const;
  // Loads in flight that were cancelled (their node no longer wanted) and not delivered.
  std::uint64_t loadsCancelled() const;
  // The intensity quantization every chunk is staged with (chunks' min and max, whether the
  // root's intensities are whole numbers), once the first load has set it; before, no chunk
  // exists. Any thread. The filter's intensity bounds are converted with it (DrawSet).
  struct IntensityLayout {
    float min = 0.0f, max = 1.0f;
    bool integral = true;
  };
  std::optional<IntensityLayout> intensityLayout() const;

  // How many queued nodes request() passes to Octree::prefetch, and the most bytes they hold.
  // Most of the queue: a hint that a reordered queue (nodes found below a proxy just read) cuts
  // short would drop fetches still wanted.
  static constexpr std::size_t kPrefetchNodes = 256;
  static constexpr std::uint64_t kPrefetchBytes = 64ull << 20;

 private:
  struct Request {
    std::int32_t index;
    bool hierarchy = false;
    OctreeNode node;
  };
  // Work is keyed by node and kind: a node's hierarchy fetch and its load are separate.
  static std::int64_t keyOf(std::int32_t index, bool hierarchy) {
    return (std::int64_t(index) << 1) | (hierarchy ? 1 : 0);
  }
  // The thread: lowers its priority and runs serve() with its parallel loops kept on itself.
  void work(std::stop_token stop);
  void serve(std::stop_token stop);
  // The loader threads' nice value (a quarter of a normal thread's CPU share under contention).
  static constexpr int kNice = 5;
  // Empty `loaded.node` (-1): cancelled, nothing to deliver.
  LoadedNode load(const Request& request, std::stop_token cancel);

  const Octree& octree_;
  ChunkLayout layout_;
  OctreeNode root_;
  std::once_flag intensity_once_;
  bool intensity_integral_ = true;
  std::atomic<bool> intensity_ready_{false};  // set (release) once layout_'s range is final

  mutable std::mutex mutex_;
  std::condition_variable_any wake_;   // workers: a request arrived, or stop
  std::condition_variable delivered_;  // waitForLoaded: a node is ready or the queue is empty
  std::deque<Request> queue_;
  std::unordered_map<std::int64_t, std::stop_source> in_flight_;  // by keyOf
  std::vector<LoadedNode> done_;
  std::uint64_t loads_started_ = 0, loads_cancelled_ = 0;
  std::vector<std::jthread> threads_;  // last: started after every other member exists
};

}  // namespace parallax
