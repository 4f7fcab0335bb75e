// Stage 5 of the conversion (convert_stages.h): the nodes above the chunks.
//
// Their points come from the chunks' roots, sampled bottom-up with the same step as inside a
// chunk (takeSample in subtree_builder.h): a node at level l takes, spaced by its spacing, from
// the points its children hold after their own sampling. The chunks' roots, now final, are
// written with the top nodes. A chunk root left without points or children is dropped.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <map>

#include "lod/convert_stages.h"
#include "lod/subtree_builder.h"

namespace parallax {

void buildTopLevels(const ConvertPlan& plan, std::vector<ChunkRoot>& roots, const Sampler& sampler,
                    OctreeBinWriter& octree, std::vector<PotreeNodeEntry>& entries) {
  const std::size_t record = plan.layout.recordSize();
  // All chunk roots' records in one array; each root's points are a range of it.
  std::uint64_t total = 0;
  for (const ChunkRoot& root : roots) total += root.records.size() / record;
  std::vector<std::byte> records(total * record);
  std::map<std::string, std::vector<std::uint32_t>> points;  // node name -> its points
  std::map<std::string, bool> has_children;
  std::uint64_t at = 0;
  for (ChunkRoot& root : roots) {
    const std::uint64_t n = root.records.size() / record;
    std::memcpy(records.data() + at * record, root.records.data(), root.records.size());
    auto& list = points[root.name];
    for (std::uint64_t i = 0; i < n; ++i) list.push_back(std::uint32_t(at + i));
    has_children[root.name] = root.has_children;
    at += n;
    std::vector<std::byte>().swap(root.records);
  }
  const Column<Int3> positions = positionsOfRecords(records.data(), total, record);

  // The top nodes: every proper prefix of a chunk's name, deepest level first.
  std::vector<std::vector<std::string>> by_level;
  for (const ChunkRoot& root : roots) {
    for (std::size_t length = 1; length < root.name.size(); ++length) {
      std::string prefix = root.name.substr(0, length);
      if (points.count(prefix)) continue;
      points[prefix];
      has_children[prefix] = true;
      if (by_level.size() < length) by_level.resize(length);
      by_level[length - 1].push_back(std::move(prefix));
    }
  }
  for (int level = int(by_level.size()) - 1; level >= 0; --level) {
    const auto& names = by_level[std::size_t(level)];
    // Looking up the lists first keeps the map unchanged while the nodes sample in parallel.
    std::vector<std::vector<std::uint32_t>*> node_lists;
    std::vector<std::vector<std::vector<std::uint32_t>*>> child_lists(names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      node_lists.push_back(&points.at(names[i]));
      for (int octant = 0; octant < 8; ++octant) {
        auto child = points.find(names[i] + char('0' + octant));
        if (child != points.end()) child_lists[i].push_back(&child->second);
      }
    }
    tbb::parallel_for(std::size_t(0), names.size(), [&](std::size_t i) {
      takeSample(positions.span(), plan.quantization, nodeBox(plan.cube, names[i]),
                 plan.spacing / double(1ull << level), child_lists[i], *node_lists[i], sampler);
    });
  }

  std::vector<std::byte> node_records;
  for (const auto& [name, list] : points) {
    if (list.empty() && !has_children.at(name)) continue;
    node_records.resize(list.size() * record);
    for (std::size_t i = 0; i < list.size(); ++i) {
      std::memcpy(node_records.data() + i * record, records.data() + std::size_t(list[i]) * record,
                  record);
    }
    const std::uint64_t offset = octree.append(node_records.data(), node_records.size());
    entries.push_back({.name = name,
                       .point_count = std::uint32_t(list.size()),
                       .byte_offset = offset,
                       .byte_size = node_records.size()});
  }
}

}  // namespace parallax
