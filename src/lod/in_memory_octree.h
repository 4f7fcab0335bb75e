// The octree of a cloud held in memory, built with the same core as the conversion
// (subtree_builder.h). The viewer uses it to show a loaded file with level of detail; tests use
// it to check the build without files.
//
// The points are reordered so that each node's points are one contiguous record range; a node's
// `byte_offset` is its first record and `byte_size` its record count (the Octree contract leaves
// both opaque). loadNode() copies that range; points() gives all of them at once.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/point_cloud.h"
#include "lod/octree.h"
#include "lod/octree_build_options.h"

namespace parallax {

class InMemoryOctree final : public Octree {
 public:
  InMemoryOctree(OctreeInfo info, std::vector<OctreeNode> nodes, PointCloud points);

  const OctreeInfo& info() const override { return info_; }
  std::span<const OctreeNode> nodes() const override { return nodes_; }
  // Never needed: the whole hierarchy is known. A call is a caller's mistake and does nothing.
  void expandHierarchy(std::int32_t node) override;
  PointCloud loadNode(const OctreeNode& node) const override;

  // Every point, in node order (node i's points are records [byte_offset, byte_offset +
  // byte_size) of it), with the source's quantization.
  const PointCloud& points() const { return points_; }

 private:
  OctreeInfo info_;
  std::vector<OctreeNode> nodes_;
  PointCloud points_;
};

// Builds the octree of `cloud` (which it copies, reordered). options.memory_bytes and
// max_chunk_points do not apply. The cube is octreeCube(cloud.bounds) when the bounds are set,
// else of the bounds computed here.
std::unique_ptr<InMemoryOctree> buildOctree(const PointCloud& cloud,
                                            const OctreeBuildOptions& options = {});

}  // namespace parallax
