#include "lod/potree_hierarchy_writer.h"

#include <cassert>
#include <cstring>
#include <deque>
#include <unordered_map>

namespace parallax {
namespace {

constexpr std::size_t kEntrySize = 22;

void putEntry(std::vector<std::byte>& out, std::uint8_t type, std::uint8_t mask,
              std::uint32_t count, std::uint64_t offset, std::uint64_t size) {
  std::byte entry[kEntrySize];
  entry[0] = std::byte(type);
  entry[1] = std::byte(mask);
  std::memcpy(entry + 2, &count, 4);  // little-endian host
  std::memcpy(entry + 6, &offset, 8);
  std::memcpy(entry + 14, &size, 8);
  out.insert(out.end(), entry, entry + kEntrySize);
}

struct ChunkEntry {
  std::int32_t node;
  bool proxy;
};

}  // namespace

std::int32_t linkPotreeNodes(std::span<PotreeNodeEntry> nodes) {
  std::unordered_map<std::string_view, std::int32_t> by_name;
  by_name.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    by_name.emplace(nodes[i].name, std::int32_t(i));
    nodes[i].children.fill(-1);
    nodes[i].child_mask = 0;
  }
  std::int32_t root = -1;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::string& name = nodes[i].name;
    if (name == "r") {
      root = std::int32_t(i);
      continue;
    }
    auto parent = by_name.find(std::string_view(name).substr(0, name.size() - 1));
    assert(parent != by_name.end() && "every node's parent must be in the list");
    const int octant = name.back() - '0';
    PotreeNodeEntry& p = nodes[std::size_t(parent->second)];
    p.children[std::size_t(octant)] = std::int32_t(i);
    p.child_mask |= std::uint8_t(1u << octant);
  }
  assert(root >= 0 && "the node list must hold the root 'r'");
  return root;
}

EncodedHierarchy encodePotreeHierarchy(std::span<const PotreeNodeEntry> nodes, std::int32_t root,
                                       int step) {
  // First the chunks' contents (which nodes, which of them proxies), then their offsets, then the
  // bytes: a proxy's entry needs the offset of a chunk listed after its own.
  std::vector<std::vector<ChunkEntry>> chunks;
  std::unordered_map<std::int32_t, std::size_t> chunk_of_node;
  std::deque<std::int32_t> chunk_roots{root};
  EncodedHierarchy result;
  while (!chunk_roots.empty()) {
    const std::int32_t chunk_root = chunk_roots.front();
    chunk_roots.pop_front();
    chunk_of_node[chunk_root] = chunks.size();
    std::vector<ChunkEntry> entries;
    const int base_level = int(nodes[std::size_t(chunk_root)].name.size()) - 1;
    std::deque<std::int32_t> queue{chunk_root};
    while (!queue.empty()) {
      const std::int32_t index = queue.front();
      queue.pop_front();
      const PotreeNodeEntry& node = nodes[std::size_t(index)];
      const int level = int(node.name.size()) - 1;
      result.depth = std::max(result.depth, level);
      const bool proxy = level == base_level + step && node.child_mask != 0;
      entries.push_back({index, proxy});
      if (proxy) {
        chunk_roots.push_back(index);
        continue;
      }
      for (int octant = 0; octant < 8; ++octant) {
        if (node.child_mask & (1u << octant)) queue.push_back(node.children[std::size_t(octant)]);
      }
    }
    chunks.push_back(std::move(entries));
  }
  std::vector<std::uint64_t> chunk_offset(chunks.size());
  std::uint64_t offset = 0;
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    chunk_offset[c] = offset;
    offset += chunks[c].size() * kEntrySize;
  }
  result.bytes.reserve(offset);
  for (const auto& chunk : chunks) {
    for (const ChunkEntry& entry : chunk) {
      const PotreeNodeEntry& node = nodes[std::size_t(entry.node)];
      if (entry.proxy) {
        const std::size_t target = chunk_of_node.at(entry.node);
        putEntry(result.bytes, 2, node.child_mask, node.point_count, chunk_offset[target],
                 chunks[target].size() * kEntrySize);
      } else {
        putEntry(result.bytes, node.child_mask != 0 ? 0 : 1, node.child_mask, node.point_count,
                 node.byte_offset, node.byte_size);
      }
    }
  }
  result.first_chunk_size = chunks.front().size() * kEntrySize;
  return result;
}

}  // namespace parallax
