// hierarchy.bin of a Potree 2.0 directory: one chunk at a time into OctreeNodes.
//
// The format (PotreeConverter 2 as it really writes it; docs/FORMATS.md): 22-byte entries, little
// endian: uint8 type (0 inner, 1 leaf, 2 proxy), uint8 child mask, uint32 point count, uint64
// byte offset, uint64 byte size. A chunk lists a subtree breadth-first, a node's children
// following in the bit order of its mask; the first entry is the chunk's own top node. A proxy's
// offset and size are those of another chunk whose first entry is that node again; its children
// are listed there, never in the proxy's chunk.
//
// What the reader trusts and what it does not:
// - The child mask decides which children exist, never the type byte (PotreeConverter writes
//   type 1 for most inner nodes); type 2 alone marks a proxy.
// - Entries after the last one the masks reach are ignored (PotreeConverter leaves some);
//   a mask naming more nodes than the chunk lists is an error.
// - Data ranges are checked against octree.bin (inside it, byteSize = points * record size),
//   proxy ranges against hierarchy.bin (inside it, whole entries), levels against a depth limit.
// Each failure is an InputError naming hierarchy.bin, the entry's byte offset, the node, what
// was expected and what was found.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lod/octree.h"

namespace parallax {

inline constexpr std::size_t kPotreeEntrySize = 22;
// Deeper levels have nodes smaller than what int32 positions over the root cube can resolve.
inline constexpr int kPotreeMaxLevel = 31;

struct PotreeEntry {
  std::uint8_t type = 0;  // 0 inner, 1 leaf, 2 proxy
  std::uint8_t child_mask = 0;
  std::uint32_t point_count = 0;
  std::uint64_t byte_offset = 0;
  std::uint64_t byte_size = 0;
};

// Decodes the 22 bytes of one entry.
PotreeEntry decodePotreeEntry(std::span<const std::byte, kPotreeEntrySize> bytes);

// What entries are checked against.
struct PotreeHierarchyLimits {
  std::string hierarchy_file, octree_file;  // for messages
  std::uint64_t hierarchy_size = 0;         // bytes of hierarchy.bin
  std::uint64_t octree_size = 0;            // bytes of octree.bin
  std::uint64_t record_size = 0;            // bytes per point
};

// Checks a chunk range (a proxy's, or the first chunk's) against hierarchy.bin: non-empty, whole
// entries, inside the file. `where` is the byte offset of the entry or field that names it.
void checkPotreeChunkRange(std::uint64_t offset, std::uint64_t size, const std::string& node,
                           std::uint64_t where, const PotreeHierarchyLimits& limits);

// Checks a node's data range against octree.bin. `where`: as above; without it (a node whose
// entry is not at hand) the error names octree.bin at the range's start.
void checkPotreeDataRange(const PotreeEntry& entry, const std::string& node,
                          std::optional<std::uint64_t> where, const PotreeHierarchyLimits& limits);

// Reads one chunk (`bytes`, which start at `chunk_offset` in hierarchy.bin) whose first entry
// is nodes[top]: sets that node from the entry and appends its descendants listed in the chunk
// to `nodes`. A proxy node is left with hierarchy_pending set and its chunk's range in
// byte_offset / byte_size (the reader resolves it later). nodes[top] must have no children yet.
void readPotreeChunk(std::span<const std::byte> bytes, std::uint64_t chunk_offset, std::int32_t top,
                     std::vector<OctreeNode>& nodes, const PotreeHierarchyLimits& limits);

}  // namespace parallax
