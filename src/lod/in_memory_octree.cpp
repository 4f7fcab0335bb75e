#include "lod/in_memory_octree.h"

#include <tbb/parallel_for.h>

#include <cassert>
#include <cstring>

#include "lod/subtree_builder.h"

namespace parallax {
namespace {

// Copies the same records from every column: `pick(i)` is the source record of target i.
template <class Pick>
PointCloud copyRecords(const PointCloud& cloud, std::uint64_t count, Pick pick) {
  PointCloud out;
  out.count = count;
  out.quantization = cloud.quantization;
  out.source = cloud.source;
  auto copyColumn = [&](const auto& from, auto& to) {
    if (from.empty()) return;
    to = std::remove_reference_t<decltype(to)>(count);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1 << 14), [&](const auto& range) {
      for (std::uint64_t i = range.begin(); i != range.end(); ++i) to[i] = from[pick(i)];
    });
  };
  copyColumn(cloud.positions, out.positions);
  copyColumn(cloud.colors, out.colors);
  copyColumn(cloud.normals, out.normals);
  copyColumn(cloud.intensity, out.intensity);
  copyColumn(cloud.classification, out.classification);
  for (const ScalarColumn& column : cloud.scalars) {
    ScalarColumn copy{.name = column.name, .type = column.type};
    const std::size_t size = scalarSize(column.type);
    copy.data = ByteBuffer(count * size);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1 << 14), [&](const auto& range) {
      for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
        std::memcpy(copy.data.data() + i * size, column.data.data() + pick(i) * size, size);
      }
    });
    out.scalars.push_back(std::move(copy));
  }
  return out;
}

}  // namespace

PointCloud gatherPoints(const PointCloud& cloud, std::span<const std::uint32_t> indices) {
  return copyRecords(cloud, indices.size(), [&](std::uint64_t i) { return indices[i]; });
}

PointCloud slicePoints(const PointCloud& cloud, std::uint64_t first, std::uint64_t count) {
  assert(first + count <= cloud.count && "slice past the end of the cloud");
  return copyRecords(cloud, count, [&](std::uint64_t i) { return first + i; });
}

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
