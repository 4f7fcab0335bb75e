#include "lod/potree_octree_writer.h"

#include <fstream>
#include <mutex>
#include <stdexcept>

#include "lod/convert_stages.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_converter.h"
#include "lod/potree_hierarchy_writer.h"
#include "lod/potree_layout.h"

namespace parallax {
namespace {

void writeFile(const std::filesystem::path& path, const void* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

struct EncodedNode {
  ByteBuffer records;
  std::uint64_t bytes = 0;
  AttributeStats stats;
};

}  // namespace

PotreeWriteResult writePotree(Octree& octree, const std::filesystem::path& output,
                              const PotreeWriteOptions& options) {
  std::filesystem::path target = std::filesystem::absolute(output).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  checkPotreeOutput(target);
  expandWholeOctree(octree);
  const auto nodes = octree.nodes();
  const std::vector<std::int32_t> order = nodesByLevel(octree);
  const OctreeInfo& info = octree.info();

  // The layout of the nodes' columns (every node has the same), from the first with points.
  PointCloud prototype;
  for (const std::int32_t n : order) {
    if (nodes[std::size_t(n)].point_count > 0) {
      prototype = octree.loadNode(nodes[std::size_t(n)]);
      break;
    }
  }
  const PotreeLayout layout = PotreeLayout::fromCloud(prototype);
  const std::size_t record_size = layout.recordSize();

  std::filesystem::create_directories(target.parent_path());
  TemporaryDirectory temp(partialPathFor(target));
  OctreeBinWriter octree_bin(temp.path() / "octree.bin", 0);
  std::vector<PotreeNodeEntry> entries(nodes.size());
  AttributeStats stats = layout.emptyStats();
  PotreeWriteResult result;
  forEachNodeInBatches<EncodedNode>(
      octree, order, std::max<std::uint64_t>(1, options.batch_points),
      [&](std::int32_t n, EncodedNode& slot) {
        const OctreeNode& node = nodes[std::size_t(n)];
        slot.bytes = 0;
        slot.stats = layout.emptyStats();
        if (node.point_count == 0) return;
        const PointCloud cloud = octree.loadNode(node);
        slot.bytes = cloud.count * record_size;
        if (slot.records.size() < slot.bytes) slot.records = ByteBuffer(std::size_t(slot.bytes));
        layout.encode(cloud, 0, cloud.count, info.quantization, slot.records.data(), slot.stats);
      },
      [&](std::int32_t n, EncodedNode& slot) {
        const OctreeNode& node = nodes[std::size_t(n)];
        PotreeNodeEntry& entry = entries[std::size_t(n)];
        entry.name = node.name;
        entry.point_count = std::uint32_t(slot.bytes / std::max<std::size_t>(1, record_size));
        entry.byte_offset = octree_bin.append(slot.records.data(), std::size_t(slot.bytes));
        entry.byte_size = slot.bytes;
        stats.merge(slot.stats);
        result.points += entry.point_count;
        if (options.progress) options.progress->advance(entry.point_count);
      });
  octree_bin.close();

  const std::int32_t root = linkPotreeNodes(entries);
  const EncodedHierarchy hierarchy = encodePotreeHierarchy(entries, root);
  writeFile(temp.path() / "hierarchy.bin", hierarchy.bytes.data(), hierarchy.bytes.size());
  const std::string metadata = potreeMetadataText(
      {.points = result.points,
       .quantization = info.quantization,
       .spacing = info.spacing,
       .cube = info.cube,
       .layout = &layout,
       .stats = &stats,
       .first_chunk_size = hierarchy.first_chunk_size,
       .depth = hierarchy.depth,
       .name = options.name.empty() ? target.filename().string() : options.name});
  writeFile(temp.path() / "metadata.json", metadata.data(), metadata.size());
  if (std::filesystem::exists(target)) std::filesystem::remove_all(target);
  std::filesystem::rename(temp.path(), target);
  temp.release();
  result.nodes = entries.size();
  result.depth = hierarchy.depth;
  return result;
}

}  // namespace parallax
