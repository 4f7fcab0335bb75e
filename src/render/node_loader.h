// Background loading of octree nodes: worker threads read nodes (Octree::loadNode) and stage them
// for the GPU (stagePointChunk: Morton order, chunk-relative floats), so that the frame loop only
// copies ready bytes into a buffer and never waits on the disk.
//
// The frame loop hands over the nodes it wants each frame, most urgent first; the queue is
// replaced, not appended to, so a node the camera has turned away from is dropped before it is
// read. Loads already in flight finish and are delivered (the cache may still want them).
//
// Why own threads and not TBB tasks: a load mostly waits on the disk, and a TBB worker blocked
// in read() is a core taken from the parallel loops (staging, conversion) that TBB runs. The
// staging inside a load does use TBB.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

#include "lod/octree.h"
#include "render/point_buffers.h"

namespace parallax {

struct LoadedNode {
  std::int32_t node = -1;
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
  NodeLoader(const NodeLoader&) = delete;
  NodeLoader& operator=(const NodeLoader&) = delete;

  // Replaces the queue by `wanted` (indices into `nodes`, most urgent first). Nodes in flight or
  // delivered and not yet taken are not queued again. `nodes` is read here only (the loader
  // keeps copies), so the caller may expand the hierarchy afterwards.
  void request(std::span<const OctreeNode> nodes, std::span<const std::int32_t> wanted);
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

 private:
  struct Request {
    std::int32_t index;
    OctreeNode node;
  };
  void work(std::stop_token stop);
  LoadedNode load(const Request& request);

  const Octree& octree_;
  ChunkLayout layout_;
  OctreeNode root_;
  std::once_flag intensity_once_;

  mutable std::mutex mutex_;
  std::condition_variable_any wake_;   // workers: a request arrived, or stop
  std::condition_variable delivered_;  // waitForLoaded: a node is ready or the queue is empty
  std::deque<Request> queue_;
  std::unordered_set<std::int32_t> in_flight_;
  std::vector<LoadedNode> done_;
  std::uint64_t loads_started_ = 0;
  std::vector<std::jthread> threads_;  // last: started after every other member exists
};

}  // namespace parallax
