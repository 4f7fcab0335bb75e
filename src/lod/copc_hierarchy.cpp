#include "lod/copc_hierarchy.h"

#include <algorithm>
#include <cassert>

#include "core/error.h"

namespace parallax {
namespace {

constexpr const char* kHierarchyHint =
    "the file's COPC hierarchy is damaged; a plain LAZ reader may still read its points "
    "(`parallax convert FILE.copc.laz -o FILE.las` does not use the hierarchy)";

std::string entryName(const std::string& page, std::size_t index, const CopcKey& key) {
  std::string out = page;
  out += ", entry ";
  out += std::to_string(index);
  out += " (key ";
  out += key.text();
  out += ')';
  return out;
}

[[noreturn]] void fail(const std::string& file, std::uint64_t offset, const std::string& element,
                       std::string expected, std::string found) {
  throw InputError({.file = file,
                    .byte_offset = offset,
                    .element = element,
                    .expected = std::move(expected),
                    .found = std::move(found),
                    .hint = kHierarchyHint});
}

}  // namespace

CopcHierarchy::CopcHierarchy(CopcLimits limits) : limits_(std::move(limits)) {
  chunk_taken_.assign(limits_.chunk_count, 0);
}

std::string CopcHierarchy::pageName(std::uint64_t offset, const std::string& node) const {
  std::string out = "hierarchy page at byte ";
  out += std::to_string(offset);
  out += " (of node ";
  out += node;
  out += ')';
  return out;
}

void CopcHierarchy::addPageRange(std::uint64_t offset, std::uint64_t size,
                                 const std::string& element, std::uint64_t entry_offset) {
  const std::string range = "bytes " + std::to_string(offset) + "-" + std::to_string(offset + size);
  if (size == 0 || size % kCopcEntrySize != 0) {
    fail(limits_.file, entry_offset, element, "a hierarchy page of whole 32-byte entries",
         std::to_string(size) + " bytes");
  }
  if (offset > limits_.file_size || size > limits_.file_size - offset) {
    fail(limits_.file, entry_offset, element,
         "a hierarchy page inside the file (" + std::to_string(limits_.file_size) + " bytes)",
         range);
  }
  const std::uint64_t end = offset + size;
  if (offset < limits_.data_end && end > limits_.data_begin) {
    fail(limits_.file, entry_offset, element,
         "a hierarchy page outside the point data (bytes " + std::to_string(limits_.data_begin) +
             "-" + std::to_string(limits_.data_end) + ")",
         range);
  }
  // The page starting at or before `offset`, and the one after it, are the only candidates.
  auto next = pages_.upper_bound(offset);
  if (next != pages_.begin()) {
    auto before = std::prev(next);
    if (before->second > offset) {
      const bool same = before->first == offset;
      fail(limits_.file, entry_offset, element, "a hierarchy page no other entry names",
           same ? range + ", a page already named (a loop)"
                : range + ", overlapping the page at bytes " + std::to_string(before->first) + "-" +
                      std::to_string(before->second));
    }
  }
  if (next != pages_.end() && next->first < end) {
    fail(limits_.file, entry_offset, element, "a hierarchy page no other entry names",
         range + ", overlapping the page at bytes " + std::to_string(next->first) + "-" +
             std::to_string(next->second));
  }
  pages_.emplace(offset, end);
}

void CopcHierarchy::checkChunk(const CopcEntry& e, const std::string& element,
                               std::uint64_t entry_offset) const {
  if (e.point_count < -1 || e.byte_size < 0) {
    fail(limits_.file, entry_offset, element,
         "a point count of -1 (a child page) or more and a byte size of 0 or more",
         std::to_string(e.point_count) + " points, " + std::to_string(e.byte_size) + " bytes");
  }
  if (e.point_count == 0) {
    if (e.byte_size != 0) {
      fail(limits_.file, entry_offset + 24, element, "no bytes for a node of 0 points",
           std::to_string(e.byte_size) + " bytes at byte " + std::to_string(e.offset));
    }
    return;
  }
  const auto found = limits_.chunks.find(e.offset);
  if (found == limits_.chunks.end()) {
    fail(limits_.file, entry_offset + 16, element,
         "the offset of one of the " + std::to_string(limits_.chunk_count) +
             " chunks of the LAZ chunk table",
         "byte " + std::to_string(e.offset) + ", where no chunk starts");
  }
  const CopcLimits::Chunk& chunk = found->second;
  if (chunk.bytes != std::uint64_t(e.byte_size) || chunk.points != std::uint64_t(e.point_count)) {
    fail(limits_.file, entry_offset + 24, element,
         "the chunk table's " + std::to_string(chunk.points) + " points in " +
             std::to_string(chunk.bytes) + " bytes for chunk " + std::to_string(chunk.index) +
             " at byte " + std::to_string(e.offset),
         std::to_string(e.point_count) + " points in " + std::to_string(e.byte_size) + " bytes");
  }
}

void CopcHierarchy::addRoot(std::uint64_t page_offset, std::uint64_t page_size,
                            std::vector<OctreeNode>& nodes) {
  assert(nodes.empty() && "addRoot: the root comes first");
  addPageRange(page_offset, page_size, "root hierarchy page (copc info VLR)",
               kCopcInfoPayloadOffset + 40);
  OctreeNode root;
  root.name = "r";
  root.box = limits_.cube;
  root.spacing = limits_.spacing;
  root.children.fill(-1);
  root.hierarchy_pending = true;
  root.byte_offset = page_offset;
  root.byte_size = page_size;
  nodes.push_back(std::move(root));
  by_name_.emplace("r", 0);
  pending_ = 1;
}

CopcEntry CopcHierarchy::ownEntry(std::span<const std::byte> page, const OctreeNode& node) const {
  const std::string page_name = pageName(node.byte_offset, node.name);
  const CopcKey key = *copcKeyOfName(node.name);
  const std::vector<CopcEntry> entries = parseCopcPage(page);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (entries[i].key != key) continue;
    const std::string element = entryName(page_name, i, key);
    const std::uint64_t at = node.byte_offset + i * kCopcEntrySize;
    if (entries[i].point_count == -1) {
      fail(limits_.file, at + 28, element, "the entry of the node the page was named for",
           "another child page (-1 points) for the same key");
    }
    checkChunk(entries[i], element, at);
    return entries[i];
  }
  fail(limits_.file, node.byte_offset, page_name, "an entry for key " + key.text(),
       "none in its " + std::to_string(entries.size()) + " entries");
}

void CopcHierarchy::readPage(std::span<const std::byte> page, std::int32_t top,
                             std::vector<OctreeNode>& nodes) {
  assert(top >= 0 && std::size_t(top) < nodes.size() && nodes[std::size_t(top)].hierarchy_pending);
  const std::uint64_t page_offset = nodes[std::size_t(top)].byte_offset;
  const std::string page_name = pageName(page_offset, nodes[std::size_t(top)].name);
  const CopcKey page_key = *copcKeyOfName(nodes[std::size_t(top)].name);
  const std::vector<CopcEntry> entries = parseCopcPage(page);

  // Checks of each entry on its own, then the page's own entry, then the others by level (a
  // parent before its children, whatever the page's order).
  std::vector<std::size_t> order;
  std::size_t own = entries.size();
  std::unordered_map<std::string, std::size_t> in_page;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const CopcEntry& e = entries[i];
    const std::uint64_t at = page_offset + i * kCopcEntrySize;
    const std::string element = entryName(page_name, i, e.key);
    if (!e.key.valid()) {
      fail(limits_.file, at, element,
           "a key of level 0-" + std::to_string(kCopcMaxLevel) +
               " with x, y and z in 0 .. 2^level - 1",
           "key " + e.key.text());
    }
    if (!e.key.within(page_key)) {
      fail(limits_.file, at, element,
           "a key at or below the page's node (key " + page_key.text() + ")",
           "key " + e.key.text());
    }
    if (!in_page.emplace(copcNodeName(e.key), i).second) {
      fail(limits_.file, at, element, "each key once in a page", "key " + e.key.text() + " again");
    }
    if (e.point_count == -1) {
      if (e.key == page_key) {
        fail(limits_.file, at + 28, element, "the page's own node with its points",
             "another child page (-1 points) for it");
      }
    } else {
      checkChunk(e, element, at);
    }
    if (e.key == page_key) {
      own = i;
    } else {
      order.push_back(i);
    }
  }
  if (own == entries.size()) {
    fail(limits_.file, page_offset, page_name, "an entry for key " + page_key.text(),
         "none in its " + std::to_string(entries.size()) + " entries");
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return entries[a].key.level < entries[b].key.level;
  });

  auto claim = [&](const CopcEntry& e, const std::string& element, std::uint64_t at) {
    if (e.point_count <= 0) return;
    const std::size_t index = limits_.chunks.at(e.offset).index;
    if (chunk_taken_[index]) {
      fail(limits_.file, at + 16, element, "a chunk no other node has",
           "chunk " + std::to_string(index) + " at byte " + std::to_string(e.offset) +
               ", already another node's");
    }
    chunk_taken_[index] = 1;
  };

  {
    OctreeNode& node = nodes[std::size_t(top)];
    const CopcEntry& e = entries[own];
    claim(e, entryName(page_name, own, e.key), page_offset + own * kCopcEntrySize);
    node.point_count = std::uint32_t(e.point_count);
    node.byte_offset = e.offset;
    node.byte_size = std::uint64_t(e.byte_size);
    node.hierarchy_pending = false;
    points_ += node.point_count;
    --pending_;
  }
  for (const std::size_t i : order) {
    const CopcEntry& e = entries[i];
    const std::uint64_t at = page_offset + i * kCopcEntrySize;
    const std::string element = entryName(page_name, i, e.key);
    const std::string name = copcNodeName(e.key);
    if (by_name_.count(name) != 0) {
      fail(limits_.file, at, element, "each key in one page only",
           "key " + e.key.text() + ", listed by an earlier page too");
    }
    const std::string parent_name = copcNodeName(e.key.parent());
    const auto parent_in_page = in_page.find(parent_name);
    const auto parent = by_name_.find(parent_name);
    if (parent == by_name_.end() ||
        (parent_in_page != in_page.end() && entries[parent_in_page->second].point_count == -1)) {
      fail(limits_.file, at, element,
           "the parent's entry (key " + e.key.parent().text() + ") in the page",
           parent == by_name_.end() ? "none: a node without a parent"
                                    : "a child page (-1 points) for the parent");
    }
    if (e.point_count == -1) {
      addPageRange(e.offset, std::uint64_t(std::max(e.byte_size, 0)), element, at + 16);
    } else {
      claim(e, element, at);
    }
    OctreeNode node;
    node.name = name;
    node.level = e.key.level;
    node.box = copcNodeBox(limits_.cube, e.key);
    node.spacing = limits_.spacing / double(std::int64_t{1} << e.key.level);
    node.children.fill(-1);
    node.parent = parent->second;
    node.hierarchy_pending = e.point_count == -1;
    node.point_count = e.point_count == -1 ? 0 : std::uint32_t(e.point_count);
    node.byte_offset = e.offset;
    node.byte_size = std::uint64_t(e.byte_size);
    const std::int32_t index = std::int32_t(nodes.size());
    OctreeNode& parent_node = nodes[std::size_t(parent->second)];
    parent_node.child_mask = std::uint8_t(parent_node.child_mask | (1u << e.key.digit()));
    parent_node.children[std::size_t(e.key.digit())] = index;
    points_ += node.point_count;
    pending_ += node.hierarchy_pending ? 1 : 0;
    by_name_.emplace(name, index);
    nodes.push_back(std::move(node));
  }
  ++pages_read_;
  if (pending_ == 0 && points_ != limits_.header_points) {
    throw InputError(
        {.file = limits_.file,
         .element = "COPC hierarchy (" + std::to_string(pages_read_) + " pages)",
         .expected =
             "nodes holding the header's " + std::to_string(limits_.header_points) + " points",
         .found = std::to_string(points_) + " points in " + std::to_string(nodes.size()) + " nodes",
         .hint = kHierarchyHint});
  }
}

}  // namespace parallax
