#include "lod/in_memory_octree.h"

#include <cassert>

#include "core/point_gather.h"
#include "lod/subtree_builder.h"

namespace parallax {

InMemoryOctree::InMemoryOctree(OctreeInfo info, std::vector<OctreeNode> nodes, PointCloud points)
    : info_(std::move(info)), nodes_(std::move(nodes)), points_(std::move(points)) {}

void InMemoryOctree::expandHierarchy(std::int32_t) {}

PointCloud InMemoryOctree::loadNode(const OctreeNode& node) const {
  PointCloud cloud = slicePoints(points_, node.byte_offset, node.byte_size);
  cloud.computeBounds();
  return cloud;
}

std::unique_ptr<InMemoryOctree> buildOctree(const PointCloud& cloud,
                                            const OctreeBuildOptions& options) {
  assert(cloud.count <= UINT32_MAX && "the in-memory octree indexes points with 32 bits");
  Bounds3 bounds = cloud.bounds;
  if (bounds.empty() && cloud.count > 0) {
    PointCloud copy_for_bounds;  // computeBounds needs a PointCloud; bounds only from positions
    copy_for_bounds.count = cloud.count;
    copy_for_bounds.quantization = cloud.quantization;
    copy_for_bounds.positions = cloud.positions.clone();
    copy_for_bounds.computeBounds();
    bounds = copy_for_bounds.bounds;
  }
  const Bounds3 cube = octreeCube(bounds);
  const double spacing = rootSpacing(cube, options);
  const auto sampler = makeSampler(options.sampling);
  BuiltSubtree built =
      buildSubtree(cloud.positions.span(), cloud.quantization,
                   {.name = "r", .level = 0, .box = cube, .spacing = spacing}, options, *sampler);

  std::vector<OctreeNode> nodes;
  nodes.reserve(built.nodes.size());
  for (const BuiltNode& b : built.nodes) {
    OctreeNode node;
    node.name = b.name;
    node.level = b.level;
    node.box = nodeBox(cube, b.name);
    node.spacing = spacing / double(1ull << b.level);
    node.point_count = b.count;
    node.child_mask = b.child_mask;
    for (int i = 0; i < 8; ++i) node.children[std::size_t(i)] = b.children[std::size_t(i)];
    node.parent = b.parent;
    node.byte_offset = b.first;
    node.byte_size = b.count;
    nodes.push_back(std::move(node));
  }
  PointCloud points = gatherPoints(cloud, built.order);
  points.bounds = bounds;

  OctreeInfo info;
  info.point_count = cloud.count;
  info.bounds = bounds;
  info.cube = cube;
  info.quantization = cloud.quantization;
  info.spacing = spacing;
  info.attributes = cloud.attributeNames();
  info.has_colors = cloud.hasColors();
  info.has_normals = cloud.hasNormals();
  info.has_intensity = cloud.hasIntensity();
  info.has_classification = cloud.hasClassification();
  return std::make_unique<InMemoryOctree>(std::move(info), std::move(nodes), std::move(points));
}

}  // namespace parallax
