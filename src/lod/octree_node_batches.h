// Node by node through a whole octree, in parallel and in order: what the writers that re-encode
// an octree into another format share (the COPC writer, the Potree writer of any octree).
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "lod/octree.h"

namespace parallax {

// Reads every hierarchy page or chunk (expandHierarchy on every pending node, appended ones
// included).
inline void expandWholeOctree(Octree& octree) {
  for (std::size_t i = 0; i < octree.nodes().size(); ++i) {
    if (octree.nodes()[i].hierarchy_pending) octree.expandHierarchy(std::int32_t(i));
  }
}

// The nodes of an expanded octree level by level (then by name): the order the writers store
// them in, so that the top of the tree, which a viewer reads first, is at the start.
inline std::vector<std::int32_t> nodesByLevel(const Octree& octree) {
  const auto nodes = octree.nodes();
  std::vector<std::int32_t> order(nodes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::int32_t(i);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    const OctreeNode& x = nodes[std::size_t(a)];
    const OctreeNode& y = nodes[std::size_t(b)];
    return x.level != y.level ? x.level < y.level : x.name < y.name;
  });
  return order;
}

// For the nodes of `order`, a batch at a time (consecutive nodes holding about `batch_points`
// points together, at least one node): `encode(node, slot)` on every core for the batch's nodes,
// each with a Slot of its own, then `write(node, slot)` on the calling thread in order. Memory:
// one batch of slots (they are reused from batch to batch). Exceptions from either end the walk
// and propagate.
template <class Slot, class Encode, class Write>
void forEachNodeInBatches(const Octree& octree, const std::vector<std::int32_t>& order,
                          std::uint64_t batch_points, Encode&& encode, Write&& write) {
  const auto nodes = octree.nodes();
  std::vector<Slot> slots;
  std::size_t begin = 0;
  while (begin < order.size()) {
    std::size_t end = begin;
    std::uint64_t points = 0;
    while (end < order.size() && (end == begin || points < batch_points)) {
      points += nodes[std::size_t(order[end])].point_count;
      ++end;
    }
    if (slots.size() < end - begin) slots.resize(end - begin);
    tbb::parallel_for(
        begin, end, [&](std::size_t i) { encode(order[i], slots[i - begin]); },
        tbb::simple_partitioner());
    for (std::size_t i = begin; i < end; ++i) write(order[i], slots[i - begin]);
    begin = end;
  }
}

}  // namespace parallax
