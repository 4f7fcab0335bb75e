// hierarchy.bin of a Potree 2.0 directory, from the list of nodes.
//
// Entries are 22 bytes, little endian: uint8 type (0 inner, 1 leaf, 2 proxy), uint8 child mask,
// uint32 point count, uint64 byte offset, uint64 byte size. The file is cut into chunks of
// `step` levels: the chunk of a node lists, breadth-first with children in bit order, the node
// and its descendants down to `step` levels below it; a descendant exactly `step` levels below
// that has children of its own is a proxy there (offset and size of its own chunk in
// hierarchy.bin, which starts with the node again, with its octree.bin range). The root's chunk
// comes first; its size is metadata "hierarchy.firstChunkSize".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace parallax {

struct PotreeNodeEntry {
  std::string name;  // "r", "r0", ...
  std::uint8_t child_mask = 0;
  std::array<std::int32_t, 8> children{-1, -1, -1, -1, -1, -1, -1, -1};  // into the node list
  std::uint32_t point_count = 0;
  std::uint64_t byte_offset = 0;  // in octree.bin
  std::uint64_t byte_size = 0;
};

struct EncodedHierarchy {
  std::vector<std::byte> bytes;
  std::uint64_t first_chunk_size = 0;
  int depth = 0;  // the deepest level
};

// Fills every node's `children` from the names (node names must be unique, every node's parent
// present). Returns the index of the root "r".
std::int32_t linkPotreeNodes(std::span<PotreeNodeEntry> nodes);

// Encodes linked nodes (linkPotreeNodes) starting at `root`.
EncodedHierarchy encodePotreeHierarchy(std::span<const PotreeNodeEntry> nodes, std::int32_t root,
                                       int step = 4);

}  // namespace parallax
