// The records that make a LAZ 1.4 file a COPC 1.0 file (Cloud Optimized Point Cloud,
// https://copc.io, "COPC specification 1.0"), shared by the COPC reader and writer.
//
// A COPC file is an ordinary LAZ 1.4 file of point format 6, 7 or 8 (layered chunks, variable
// chunk size, the usual chunk table) whose chunks are the nodes of an octree, plus:
//   - the "info" VLR, user id "copc", record 1, which must be the first VLR (its payload starts
//     at byte 429 of the file): 160 bytes, little endian
//       double center x, y, z; double halfsize (the root cube is center +- halfsize);
//       double spacing (of the root's points, halved per level);
//       uint64 root hierarchy page offset, uint64 its size (bytes);
//       double GPS time minimum, maximum; uint64 reserved[11] (zero);
//   - the hierarchy, an EVLR of user id "copc", record 1000, holding one or more pages; a page
//     is entries of 32 bytes
//       int32 level, x, y, z (the VoxelKey: the node's cube is number x, y, z of the 2^level
//       cubes a side at that level; +x, +y, +z grow with the index);
//       uint64 offset; int32 byte size; int32 point count
//     where a point count >= 0 gives the node's chunk (offset and size of its LAZ chunk; 0
//     points: a node without points, offset and size 0) and -1 says that offset and size are
//     those of a child page, which holds the entry of that same key and of nodes below it.
//
// Node names: a key maps to Potree's name of the same cube ("r", then one digit a level, the
// digit of a level being 4 * x bit + 2 * y bit + z bit), so the octree interface's child order
// (octree.h: bit 4 = +x, 2 = +y, 1 = +z) holds for COPC too.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/bounds.h"

namespace parallax {

inline constexpr const char* kCopcUserId = "copc";
inline constexpr std::uint16_t kCopcInfoRecordId = 1;
inline constexpr std::uint16_t kCopcHierarchyRecordId = 1000;
inline constexpr std::size_t kCopcInfoSize = 160;
inline constexpr std::size_t kCopcEntrySize = 32;
// Where the info VLR's header and payload are: right after the 375-byte LAS 1.4 header.
inline constexpr std::uint64_t kCopcInfoVlrOffset = 375;
inline constexpr std::uint64_t kCopcInfoPayloadOffset = 375 + 54;
// Deepest level a key may have: a cube's x, y, z index must fit an int32 (2^30 cubes a side at
// level 30), and no real tree comes near it.
inline constexpr int kCopcMaxLevel = 30;

struct CopcInfo {
  std::array<double, 3> center{};
  double halfsize = 0.0;
  double spacing = 0.0;
  std::uint64_t root_hierarchy_offset = 0;
  std::uint64_t root_hierarchy_size = 0;
  double gps_time_min = 0.0, gps_time_max = 0.0;

  Bounds3 cube() const;
};

CopcInfo parseCopcInfo(std::span<const std::byte, kCopcInfoSize> bytes);
std::array<std::byte, kCopcInfoSize> encodeCopcInfo(const CopcInfo& info);

struct CopcKey {
  std::int32_t level = 0, x = 0, y = 0, z = 0;
  friend bool operator==(const CopcKey&, const CopcKey&) = default;
  friend auto operator<=>(const CopcKey&, const CopcKey&) = default;

  // Within 0 <= level <= kCopcMaxLevel and 0 <= x, y, z < 2^level.
  bool valid() const;
  CopcKey parent() const { return {level - 1, x >> 1, y >> 1, z >> 1}; }
  // Child `digit` in Potree's order (bit 4 = +x, 2 = +y, 1 = +z).
  CopcKey child(int digit) const;
  // The digit of this key under its parent (level >= 1).
  int digit() const { return ((x & 1) << 2) | ((y & 1) << 1) | (z & 1); }
  // True when `this` is `ancestor` or lies below it.
  bool within(const CopcKey& ancestor) const;
  // "0-0-0-0" as COPC tools print keys (level-x-y-z).
  std::string text() const;
};

// "r", "r4", "r47", ... for a valid key; the key of such a name (nullopt for anything else).
std::string copcNodeName(const CopcKey& key);
std::optional<CopcKey> copcKeyOfName(const std::string& name);

// The cube of `key` inside the root cube `root`.
Bounds3 copcNodeBox(const Bounds3& root, const CopcKey& key);

struct CopcEntry {
  CopcKey key;
  std::uint64_t offset = 0;
  std::int32_t byte_size = 0;
  std::int32_t point_count = 0;  // -1: offset and byte_size are a child page's
};

// Entries of a page of `bytes.size() / 32` entries (the caller checked the size).
std::vector<CopcEntry> parseCopcPage(std::span<const std::byte> bytes);
void appendCopcEntry(const CopcEntry& entry, std::vector<std::byte>& out);

}  // namespace parallax
