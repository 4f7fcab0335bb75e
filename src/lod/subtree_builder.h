// The build core: the additive LOD octree of a set of points in a cube, in memory.
//
// Used whole by the in-memory path (the subtree is the whole octree) and per chunk by the
// out-of-core conversion (each chunk is the subtree below one node of the global octree, and
// the levels above the chunks are sampled from the chunks' roots with takeSample()).
//
// The algorithm, as Potree's: sort the points in Morton order inside the cube; split a node
// while it holds more than max_node_points (its children are the sub-ranges of the sorted
// order); then, bottom-up, let every inner node take a subsample of its children's points spaced
// by its own spacing (sampler.h). Every point ends in exactly one node. Children left empty by
// the sampling are removed.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/quantization.h"
#include "lod/octree_build_options.h"
#include "lod/sampler.h"

namespace parallax {

struct BuiltNode {
  std::string name;  // Potree name, the subtree root's name as prefix
  int level = 0;     // in the global octree
  std::uint8_t child_mask = 0;
  std::array<std::int32_t, 8> children{-1, -1, -1, -1, -1, -1, -1, -1};  // into nodes, -1: none
  std::int32_t parent = -1;                                              // -1 for node 0
  std::uint64_t first = 0;  // the node's points are order[first, first + count)
  std::uint32_t count = 0;
};

struct BuiltSubtree {
  std::vector<BuiltNode> nodes;      // breadth-first, node 0 is the subtree's root
  std::vector<std::uint32_t> order;  // indices into the positions, each node's contiguous
};

// Where the subtree sits in the global octree.
struct SubtreeFrame {
  std::string name = "r";  // of the subtree's root
  int level = 0;           // of the subtree's root
  Bounds3 box;             // the root's cube, world units
  double spacing = 0.0;    // the root's spacing, world units
};

// Builds the subtree of all `positions` (which must lie in frame.box; points on or past its
// maximum faces are clamped into the last cell). Parallel with TBB. An empty input gives a root
// with no points and no children.
BuiltSubtree buildSubtree(std::span<const Int3> positions, const Quantization& quantization,
                          const SubtreeFrame& frame, const OctreeBuildOptions& options,
                          const Sampler& sampler);

// One sampling step: the node at `box` with `spacing` takes its sample from the points of its
// children (`children[i]`, indices into `positions`, considered in order): taken points are
// appended to `node_points` and removed from their child's list, the rest keep their order.
void takeSample(std::span<const Int3> positions, const Quantization& quantization,
                const Bounds3& box, double spacing, std::span<std::vector<std::uint32_t>*> children,
                std::vector<std::uint32_t>& node_points, const Sampler& sampler);

}  // namespace parallax
