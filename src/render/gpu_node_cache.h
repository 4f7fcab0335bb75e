// The octree nodes held in GPU buffers: a least-recently-used cache under a byte budget.
//
// Each node is one PointChunk (one buffer, uploadStagedChunk). The frame loop marks the nodes
// it uses each frame (touch); making room for a new node evicts the nodes used longest ago, never
// one used in the current frame, so a frame's selection is never torn down to load part of
// itself. Among nodes last used in the same frame the deepest goes first: node selection uses a
// node's ancestors whenever it uses the node, so this order never evicts a parent before its
// child, and Potree's rule (a node is drawn only under a drawn parent) never hides a resident
// subtree for want of its root.
//
// Needs a current GL context for its whole life (it deletes its buffers when destroyed).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "render/point_buffers.h"

namespace parallax {

class GpuNodeCache {
 public:
  explicit GpuNodeCache(std::uint64_t byte_budget) : budget_(byte_budget) {}
  ~GpuNodeCache();
  GpuNodeCache(const GpuNodeCache&) = delete;
  GpuNodeCache& operator=(const GpuNodeCache&) = delete;

  // Uploads a node's staged chunk, used in `frame`, after evicting nodes not used in `frame`
  // until it fits. Returns false, uploading nothing and leaving `staged` as it was, when it cannot
  // fit (the nodes of this frame already fill the budget). The node must not be resident.
  bool insert(std::int32_t node, int level, StagedChunk& staged, std::uint64_t frame);
  // Marks a resident node as used in `frame`; ignored for nodes not resident.
  void touch(std::int32_t node, std::uint64_t frame);
  // Evicts nodes not used in `frame` until the cache holds at most `budget` bytes (after the
  // budget was lowered), least recently used first.
  void trim(std::uint64_t frame);

  // The node's chunk, or nullptr when not resident. Valid until the node is evicted.
  const PointChunk* find(std::int32_t node) const;
  bool contains(std::int32_t node) const { return entries_.count(node) != 0; }

  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t budget() const { return budget_; }
  void setBudget(std::uint64_t byte_budget) { budget_ = byte_budget; }
  std::size_t size() const { return entries_.size(); }
  std::uint64_t evictions() const { return evictions_; }
  // Resident node indices, in no particular order.
  std::vector<std::int32_t> residentNodes() const;

 private:
  struct Entry {
    PointChunk chunk;
    std::uint64_t bytes = 0;
    std::uint64_t last_used = 0;
    int level = 0;
  };
  // Evicts nodes not used in `frame`, LRU first, until bytes_ + `incoming` <= budget_. False when
  // that is impossible (what remains is all used in `frame`).
  bool makeRoom(std::uint64_t incoming, std::uint64_t frame);

  std::unordered_map<std::int32_t, Entry> entries_;  // node-based: chunk pointers stay valid
  std::uint64_t budget_ = 0;
  std::uint64_t bytes_ = 0;
  std::uint64_t evictions_ = 0;
};

}  // namespace parallax
