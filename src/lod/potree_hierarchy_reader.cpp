#include "lod/potree_hierarchy_reader.h"

#include <cassert>
#include <cstring>

#include "core/byte_order.h"
#include "core/error.h"

namespace parallax {
namespace {

// The child octant of `box`: bit 4 of the index is +x, bit 2 +y, bit 1 +z (Potree's numbering).
Bounds3 childBox(const Bounds3& box, int index) {
  Bounds3 child = box;
  const auto center = box.center();
  for (int axis = 0; axis < 3; ++axis) {
    const bool upper = (index & (4 >> axis)) != 0;
    (upper ? child.min : child.max)[axis] = center[axis];
  }
  return child;
}

[[noreturn]] void fail(const PotreeHierarchyLimits& limits, std::uint64_t where,
                       const std::string& node, std::string expected, std::string found,
                       std::string hint = {}) {
  throw InputError({.file = limits.hierarchy_file,
                    .byte_offset = where,
                    .element = "node " + node,
                    .expected = std::move(expected),
                    .found = std::move(found),
                    .hint = std::move(hint)});
}

}  // namespace

PotreeEntry decodePotreeEntry(std::span<const std::byte, kPotreeEntrySize> bytes) {
  PotreeEntry e;
  e.type = loadLE<std::uint8_t>(bytes.data());
  e.child_mask = loadLE<std::uint8_t>(bytes.data() + 1);
  e.point_count = loadLE<std::uint32_t>(bytes.data() + 2);
  e.byte_offset = loadLE<std::uint64_t>(bytes.data() + 6);
  e.byte_size = loadLE<std::uint64_t>(bytes.data() + 14);
  return e;
}

void checkPotreeChunkRange(std::uint64_t offset, std::uint64_t size, const std::string& node,
                           std::uint64_t where, const PotreeHierarchyLimits& limits) {
  if (size == 0 || size % kPotreeEntrySize != 0) {
    fail(limits, where, node, "a hierarchy chunk of whole 22-byte entries",
         std::to_string(size) + " bytes");
  }
  if (offset > limits.hierarchy_size || size > limits.hierarchy_size - offset) {
    fail(limits, where, node,
         "a hierarchy chunk inside hierarchy.bin (" + std::to_string(limits.hierarchy_size) +
             " bytes)",
         "bytes " + std::to_string(offset) + " to " + std::to_string(offset) + " + " +
             std::to_string(size),
         "hierarchy.bin is truncated or the entry is corrupt");
  }
}

void checkPotreeDataRange(const PotreeEntry& entry, const std::string& node,
                          std::optional<std::uint64_t> where, const PotreeHierarchyLimits& limits) {
  const std::string& file = where ? limits.hierarchy_file : limits.octree_file;
  if (!where) where = entry.byte_offset;
  // point_count < 2^32 and record_size is bounded by the metadata: no overflow.
  const std::uint64_t expected = std::uint64_t(entry.point_count) * limits.record_size;
  if (entry.byte_size != expected) {
    throw InputError({.file = file,
                      .byte_offset = where,
                      .element = "node " + node,
                      .expected = "byteSize = " + std::to_string(entry.point_count) + " points x " +
                                  std::to_string(limits.record_size) +
                                  " bytes = " + std::to_string(expected),
                      .found = "byteSize " + std::to_string(entry.byte_size),
                      .hint = "the point count or the byte size in hierarchy.bin is wrong (only "
                              "the DEFAULT encoding is read)"});
  }
  if (entry.byte_offset > limits.octree_size ||
      entry.byte_size > limits.octree_size - entry.byte_offset) {
    throw InputError({.file = file,
                      .byte_offset = where,
                      .element = "node " + node,
                      .expected = "a byte range inside " + limits.octree_file + " (" +
                                  std::to_string(limits.octree_size) + " bytes)",
                      .found = "bytes " + std::to_string(entry.byte_offset) + " to " +
                               std::to_string(entry.byte_offset) + " + " +
                               std::to_string(entry.byte_size),
                      .hint = "octree.bin is truncated or hierarchy.bin is corrupt"});
  }
}

void readPotreeChunk(std::span<const std::byte> bytes, std::uint64_t chunk_offset, std::int32_t top,
                     std::vector<OctreeNode>& nodes, const PotreeHierarchyLimits& limits) {
  assert(top >= 0 && std::size_t(top) < nodes.size() && "readPotreeChunk: no such node");
  assert(bytes.size() % kPotreeEntrySize == 0 && "readPotreeChunk: checkPotreeChunkRange first");
  const std::size_t entries = bytes.size() / kPotreeEntrySize;

  // The nodes of this chunk in the order their entries come: breadth first from `top`.
  std::vector<std::int32_t> queue = {top};
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const std::uint64_t where = chunk_offset + i * kPotreeEntrySize;
    if (i == entries) {
      const OctreeNode& missing = nodes[std::size_t(queue[i])];
      fail(limits, where, missing.name,
           "an entry for every node the child masks name (" + std::to_string(queue.size()) +
               " in this chunk)",
           "the chunk ends after " + std::to_string(entries) + " entries",
           "hierarchy.bin is truncated or a child mask is corrupt");
    }
    const PotreeEntry entry = decodePotreeEntry(std::span<const std::byte, kPotreeEntrySize>(
        bytes.data() + i * kPotreeEntrySize, kPotreeEntrySize));
    const std::int32_t index = queue[i];
    // No reference into `nodes` is held across the push_back below.
    const std::string name = nodes[std::size_t(index)].name;
    if (entry.type > 2) {
      fail(limits, where, name, "node type 0, 1 or 2", "type " + std::to_string(entry.type));
    }
    {
      OctreeNode& node = nodes[std::size_t(index)];
      node.point_count = entry.point_count;
      node.child_mask = entry.child_mask;
      if (entry.type == 2) {
        checkPotreeChunkRange(entry.byte_offset, entry.byte_size, name, where, limits);
        node.hierarchy_pending = true;
        node.byte_offset = entry.byte_offset;  // the chunk, until the node is expanded
        node.byte_size = entry.byte_size;
        continue;  // its children are listed in its own chunk
      }
      checkPotreeDataRange(entry, name, where, limits);
      node.hierarchy_pending = false;
      node.byte_offset = entry.byte_offset;
      node.byte_size = entry.byte_size;
    }
    if (entry.child_mask == 0) continue;
    const OctreeNode parent = nodes[std::size_t(index)];  // a copy: push_back may reallocate
    if (parent.level + 1 > kPotreeMaxLevel) {
      fail(limits, where, name, "at most " + std::to_string(kPotreeMaxLevel) + " levels",
           "children at level " + std::to_string(parent.level + 1));
    }
    for (int child = 0; child < 8; ++child) {
      if ((entry.child_mask & (1u << child)) == 0) continue;
      OctreeNode node;
      node.name = parent.name + char('0' + child);
      node.level = parent.level + 1;
      node.box = childBox(parent.box, child);
      node.spacing = parent.spacing * 0.5;
      node.children.fill(-1);
      node.parent = index;
      const auto child_index = std::int32_t(nodes.size());
      nodes.push_back(std::move(node));
      nodes[std::size_t(index)].children[std::size_t(child)] = child_index;
      queue.push_back(child_index);
    }
  }
  // Entries past queue.size() belong to no node: PotreeConverter leaves such entries; ignored.
}

}  // namespace parallax
