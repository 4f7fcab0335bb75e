// Internal to the COPC reader: the hierarchy pages turned into octree nodes, with every check
// that a page can fail (copc_format.h has the layout).
//
// The tree is read a page at a time. Each page belongs to a node still hierarchy_pending (the
// root's page to the root): it must hold that node's own entry, with its points, and may hold
// entries of nodes below it, in any order (real writers list them in hash order), and entries
// of -1 points that name a child page for a node below it (that node is appended
// hierarchy_pending, its byte range the page's, its point count 0 until the page is read).
//
// Checked, each an InputError naming the file, the page (its byte offset, and the node it was
// read for), the entry (its index and key) and the entry's byte offset:
//   - a page outside the file, not whole entries, empty, or overlapping the point data or
//     another page (a page reached twice is a loop);
//   - keys out of range (a level outside 0-30, an x, y or z outside 0 .. 2^level - 1), outside
//     the page's subtree, listed twice, or whose parent is in no page;
//   - point counts below -1, byte sizes below 0;
//   - nodes whose range is not a chunk of the LAZ chunk table, whose byte size or point count
//     disagrees with that chunk's, or whose chunk another node already has;
//   - once every page is read, node counts that do not add up to the header's point count.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/bounds.h"
#include "lod/copc_format.h"
#include "lod/octree.h"

namespace parallax {

// What the pages are checked against.
struct CopcLimits {
  std::string file;
  std::uint64_t file_size = 0;
  std::uint64_t data_begin = 0, data_end = 0;  // the chunks' bytes (first chunk .. table)
  std::uint64_t header_points = 0;
  Bounds3 cube;
  double spacing = 0.0;
  struct Chunk {
    std::uint64_t bytes = 0, points = 0;
    std::size_t index = 0;  // in the chunk table
  };
  std::unordered_map<std::uint64_t, Chunk> chunks;  // by offset
  std::size_t chunk_count = 0;
};

class CopcHierarchy {
 public:
  explicit CopcHierarchy(CopcLimits limits);

  const CopcLimits& limits() const { return limits_; }
  // Adds the root (pending, over the root page) to `nodes`, which must be empty. Checks the
  // page's range.
  void addRoot(std::uint64_t page_offset, std::uint64_t page_size, std::vector<OctreeNode>& nodes);

  // Reads the page of pending node `top` from its bytes: sets the node's points, clears its
  // flag and appends the nodes the page lists.
  void readPage(std::span<const std::byte> page, std::int32_t top, std::vector<OctreeNode>& nodes);

  // The entry of `node` (pending) in its page's bytes, checked as readPage checks it, without
  // changing anything (loader threads load a pending node's points this way).
  CopcEntry ownEntry(std::span<const std::byte> page, const OctreeNode& node) const;

  std::size_t pagesRead() const { return pages_read_; }
  std::size_t pendingNodes() const { return pending_; }
  std::uint64_t pointsSoFar() const { return points_; }

 private:
  void addPageRange(std::uint64_t offset, std::uint64_t size, const std::string& element,
                    std::uint64_t entry_offset);
  void checkChunk(const CopcEntry& entry, const std::string& element,
                  std::uint64_t entry_offset) const;
  std::string pageName(std::uint64_t offset, const std::string& node) const;

  CopcLimits limits_;
  std::map<std::uint64_t, std::uint64_t> pages_;  // offset -> end of every page named so far
  std::unordered_map<std::string, std::int32_t> by_name_;
  std::vector<std::uint8_t> chunk_taken_;  // by chunk table index
  std::size_t pages_read_ = 0;
  std::size_t pending_ = 0;
  std::uint64_t points_ = 0;
};

}  // namespace parallax
