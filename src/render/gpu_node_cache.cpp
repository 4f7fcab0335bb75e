#include "render/gpu_node_cache.h"

#include <algorithm>
#include <cassert>
#include <tuple>

namespace parallax {

GpuNodeCache::~GpuNodeCache() {
  for (auto& [node, entry] : entries_) glDeleteBuffers(1, &entry.chunk.buffer);
}

bool GpuNodeCache::insert(std::int32_t node, int level, StagedChunk& staged, std::uint64_t frame) {
  assert(!contains(node) && "GpuNodeCache::insert: the node is resident already");
  const std::uint64_t size = staged.bytes.size();
  if (!makeRoom(size, frame)) return false;
  Entry entry;
  entry.bytes = size;
  entry.last_used = frame;
  entry.level = level;
  entry.chunk = uploadStagedChunk(staged);
  entries_.emplace(node, entry);
  bytes_ += size;
  return true;
}

void GpuNodeCache::touch(std::int32_t node, std::uint64_t frame) {
  const auto found = entries_.find(node);
  if (found != entries_.end()) found->second.last_used = std::max(found->second.last_used, frame);
}

void GpuNodeCache::trim(std::uint64_t frame) {
  makeRoom(0, frame);
}

const PointChunk* GpuNodeCache::find(std::int32_t node) const {
  const auto found = entries_.find(node);
  return found == entries_.end() ? nullptr : &found->second.chunk;
}

std::vector<std::int32_t> GpuNodeCache::residentNodes() const {
  std::vector<std::int32_t> nodes;
  nodes.reserve(entries_.size());
  for (const auto& [node, entry] : entries_) nodes.push_back(node);
  return nodes;
}

bool GpuNodeCache::makeRoom(std::uint64_t incoming, std::uint64_t frame) {
  if (bytes_ + incoming <= budget_) return true;
  // Candidates, least recently used first, deepest first among equals, then by index so the
  // order is reproducible. A full sort per call is fine: a cache holds thousands of nodes, and
  // most calls return above without evicting.
  struct Candidate {
    std::uint64_t last_used;
    int level;
    std::int32_t node;
  };
  std::vector<Candidate> candidates;
  for (const auto& [node, entry] : entries_) {
    if (entry.last_used < frame) candidates.push_back({entry.last_used, entry.level, node});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.last_used, b.level, a.node) < std::tie(b.last_used, a.level, b.node);
  });
  for (const Candidate& candidate : candidates) {
    if (bytes_ + incoming <= budget_) break;
    auto found = entries_.find(candidate.node);
    glDeleteBuffers(1, &found->second.chunk.buffer);
    bytes_ -= found->second.bytes;
    entries_.erase(found);
    ++evictions_;
  }
  return bytes_ + incoming <= budget_;
}

}  // namespace parallax
