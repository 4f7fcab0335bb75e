#include "lod/potree_reader.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <map>
#include <mutex>
#include <set>

#include "core/byte_source.h"
#include "core/error.h"
#include "lod/potree_hierarchy_reader.h"
#include "lod/potree_record_reader.h"
#include "lod/potree_sources.h"

namespace parallax {
namespace {

class PotreeOctree final : public Octree {
 public:
  PotreeOctree(PotreeMetadata metadata, PotreeSources sources)
      : metadata_(std::move(metadata)),
        records_(metadata_),
        hierarchy_(std::move(sources.hierarchy)),
        octree_(std::move(sources.octree)) {
    stats_.location = sources.location;
    stats_.remote = !hierarchy_->local() || !octree_->local();
    stats_.file_bytes = sources.metadata_bytes + hierarchy_->size() + octree_->size();
    limits_ = {.hierarchy_file = hierarchy_->name(),
               .octree_file = octree_->name(),
               .hierarchy_size = hierarchy_->size(),
               .octree_size = octree_->size(),
               .record_size = metadata_.record_size};
    describe();

    OctreeNode root;
    root.name = "r";
    root.box = metadata_.cube;
    root.spacing = metadata_.spacing;
    root.children.fill(-1);
    nodes_.push_back(std::move(root));
    // The first chunk, named by metadata.json: an error there is metadata's.
    try {
      checkPotreeChunkRange(0, metadata_.hierarchy.first_chunk_size, "r", 0, limits_);
    } catch (const InputError& e) {
      InputErrorInfo info = e.info();
      info.byte_offset.reset();
      info.element = "hierarchy.firstChunkSize (of metadata.json)";
      throw InputError(std::move(info));
    }
    total_points_ = 0;
    pending_nodes_ = 0;
    readChunk(0, 0, metadata_.hierarchy.first_chunk_size);
  }

  const OctreeInfo& info() const override { return info_; }
  std::span<const OctreeNode> nodes() const override { return nodes_; }
  const PotreeMetadata& metadata() const { return metadata_; }
  PotreeReadStats readStats() const {
    PotreeReadStats stats = stats_;
    stats.hierarchy_bytes = hierarchy_bytes_.load();
    stats.node_bytes = node_bytes_.load();
    stats.nodes_loaded = nodes_loaded_.load();
    return stats;
  }

  void expandHierarchy(std::int32_t index) override {
    assert(index >= 0 && std::size_t(index) < nodes_.size() && "expandHierarchy: no such node");
    // A chain of proxies (a chunk starting with another proxy) ends, or cycles: readChunk
    // refuses a chunk read before, so this loop runs at most once per chunk of the file.
    while (nodes_[std::size_t(index)].hierarchy_pending) {
      const OctreeNode& node = nodes_[std::size_t(index)];
      readChunk(index, node.byte_offset, node.byte_size);
    }
  }

  bool hierarchyReady(std::int32_t index) const override {
    const OctreeNode& node = nodes_[std::size_t(index)];
    if (!node.hierarchy_pending || hierarchy_->local()) return true;
    std::lock_guard lock(fetched_mutex_);
    return fetched_.count(node.byte_offset) > 0;
  }

  void fetchHierarchy(const OctreeNode& node, std::stop_token cancel) const override {
    if (!node.hierarchy_pending) return;
    const std::string element = "hierarchy chunk of node " + node.name;
    std::uint64_t offset = node.byte_offset, size = node.byte_size;
    // The chunk, and the chunks a chain of proxies leads to (a chunk opening with a proxy).
    for (int step = 0; step <= kPotreeMaxLevel; ++step) {
      checkPotreeChunkRange(offset, size, node.name, offset, limits_);
      std::vector<std::byte> bytes;
      {
        std::lock_guard lock(fetched_mutex_);
        const auto it = fetched_.find(offset);
        if (it != fetched_.end()) bytes = it->second;
      }
      if (bytes.size() != size) {
        bytes.resize(size);
        hierarchy_->read(offset, bytes, {.cancel = cancel, .element = element});
        std::lock_guard lock(fetched_mutex_);
        fetched_[offset] = bytes;
      }
      const PotreeEntry first = decodePotreeEntry(
          std::span<const std::byte, kPotreeEntrySize>(bytes.data(), kPotreeEntrySize));
      if (first.type != 2) return;
      offset = first.byte_offset, size = first.byte_size;
    }
  }

  void prefetch(std::span<const OctreeNode> nodes,
                std::span<const OctreeNode> hierarchy) const override {
    if (!octree_->local()) {
      std::vector<ByteRange> ranges;
      for (const OctreeNode& node : nodes) {
        if (!node.hierarchy_pending && node.byte_size > 0) {
          ranges.push_back({node.byte_offset, node.byte_size});
        }
      }
      octree_->prefetch(ranges);
    }
    if (!hierarchy_->local()) {
      std::vector<ByteRange> ranges;
      {
        std::lock_guard lock(fetched_mutex_);
        for (const OctreeNode& node : hierarchy) {
          if (node.hierarchy_pending && !fetched_.count(node.byte_offset)) {
            ranges.push_back({node.byte_offset, node.byte_size});
          }
        }
      }
      hierarchy_->prefetch(ranges);
    }
  }

  PointCloud loadNode(const OctreeNode& node) const override {
    return loadNodeCancellable(node, {});
  }

  PointCloud loadNodeCancellable(const OctreeNode& node, std::stop_token cancel) const override {
    const std::string element = "node " + node.name;
    PotreeEntry entry;
    entry.point_count = node.point_count;
    entry.byte_offset = node.byte_offset;
    entry.byte_size = node.byte_size;
    std::optional<std::uint64_t> where;  // the entry's offset in hierarchy.bin, when read here
    if (node.hierarchy_pending) {
      // The node's own entry opens its chunk (a chain of proxies is followed a few steps).
      std::uint64_t chunk = node.byte_offset;
      for (int step = 0;; ++step) {
        checkPotreeChunkRange(chunk, kPotreeEntrySize, node.name, chunk, limits_);
        std::array<std::byte, kPotreeEntrySize> bytes;
        if (!fetchedEntry(chunk, bytes)) {
          hierarchy_->read(chunk, bytes, {.cancel = cancel, .element = element});
        }
        entry = decodePotreeEntry(bytes);
        where = chunk;
        if (entry.type > 2) {
          throw InputError({.file = limits_.hierarchy_file,
                            .byte_offset = chunk,
                            .element = element,
                            .expected = "node type 0, 1 or 2",
                            .found = "type " + std::to_string(entry.type)});
        }
        if (entry.type != 2) break;
        if (step == kPotreeMaxLevel) {
          throw InputError({.file = limits_.hierarchy_file,
                            .byte_offset = chunk,
                            .element = element,
                            .expected = "a chunk that lists the node",
                            .found = "a chain of proxies that does not end"});
        }
        chunk = entry.byte_offset;
      }
      if (entry.point_count != node.point_count) {
        throw InputError({.file = limits_.hierarchy_file,
                          .byte_offset = where,
                          .element = element,
                          .expected = std::to_string(node.point_count) +
                                      " points, as the proxy entry of the node says",
                          .found = std::to_string(entry.point_count) + " in its chunk's entry"});
      }
    }
    checkPotreeDataRange(entry, node.name, where, limits_);
    ByteBuffer bytes(entry.byte_size);
    octree_->read(entry.byte_offset, {bytes.data(), bytes.size()},
                  {.cancel = cancel, .element = element});
    node_bytes_ += entry.byte_size;
    ++nodes_loaded_;
    return records_.decode({bytes.data(), bytes.size()}, entry.point_count);
  }

 private:
  void describe() {
    info_.point_count = metadata_.points;
    info_.cube = metadata_.cube;
    info_.quantization = metadata_.quantization;
    info_.spacing = metadata_.spacing;
    info_.bounds = metadata_.cube;
    for (const auto& a : metadata_.attributes) {
      // The position attribute's min and max are the tight bounds PotreeConverter writes.
      if (a.name == "position" && a.min.size() == 3 && a.max.size() == 3) {
        info_.bounds.min = {a.min[0], a.min[1], a.min[2]};
        info_.bounds.max = {a.max[0], a.max[1], a.max[2]};
      }
      if (a.min.size() == 1 && a.max.size() == 1 && a.min[0] <= a.max[0]) {
        if (a.name == "intensity") info_.intensity_range = {{a.min[0], a.max[0]}};
        if (a.name == "gps-time" || a.name == "gps time") {
          info_.gps_time_range = {{a.min[0], a.max[0]}};
        }
      }
    }
    records_.describe(info_);
  }

  // The first entry of a fetched chunk at `chunk`, when there is one.
  bool fetchedEntry(std::uint64_t chunk, std::span<std::byte, kPotreeEntrySize> out) const {
    std::lock_guard lock(fetched_mutex_);
    const auto it = fetched_.find(chunk);
    if (it == fetched_.end() || it->second.size() < kPotreeEntrySize) return false;
    std::copy_n(it->second.begin(), kPotreeEntrySize, out.begin());
    return true;
  }

  void readChunk(std::int32_t top, std::uint64_t offset, std::uint64_t size) {
    if (!chunks_read_.insert(offset).second) {
      throw InputError({.file = limits_.hierarchy_file,
                        .byte_offset = offset,
                        .element = "node " + nodes_[std::size_t(top)].name,
                        .expected = "a proxy pointing at a hierarchy chunk not read yet",
                        .found = "a chunk already read (a cycle)"});
    }
    std::vector<std::byte> bytes;
    {
      // Fetched ahead by fetchHierarchy: taken (a chunk is read once).
      std::lock_guard lock(fetched_mutex_);
      const auto it = fetched_.find(offset);
      if (it != fetched_.end() && it->second.size() == size) {
        bytes = std::move(it->second);
        fetched_.erase(it);
      }
    }
    if (bytes.size() != size) {
      bytes.resize(size);
      hierarchy_->read(offset, bytes,
                       {.element = "hierarchy chunk of node " + nodes_[std::size_t(top)].name});
    }
    hierarchy_bytes_ += size;
    // Running totals over all nodes (a proxy's entry carries its node's count too), updated
    // for the top node and the nodes the chunk appends.
    const std::size_t first_new = nodes_.size();
    const OctreeNode& before = nodes_[std::size_t(top)];
    total_points_ -= before.point_count;  // 0 for the root before the first chunk
    pending_nodes_ -= before.hierarchy_pending ? 1 : 0;
    readPotreeChunk(bytes, offset, top, nodes_, limits_);
    const OctreeNode& after = nodes_[std::size_t(top)];
    total_points_ += after.point_count;
    pending_nodes_ += after.hierarchy_pending ? 1 : 0;
    for (std::size_t i = first_new; i < nodes_.size(); ++i) {
      total_points_ += nodes_[i].point_count;
      pending_nodes_ += nodes_[i].hierarchy_pending ? 1 : 0;
    }
    checkTotal();
  }

  // Once every chunk is read, the nodes' counts must add up to metadata's total.
  void checkTotal() const {
    if (pending_nodes_ > 0) return;
    const std::uint64_t total = total_points_;
    if (total != metadata_.points) {
      throw InputError({.file = limits_.hierarchy_file,
                        .expected = "nodes holding " + std::to_string(metadata_.points) +
                                    " points in all (metadata.json \"points\")",
                        .found = std::to_string(total) + " points in " +
                                 std::to_string(nodes_.size()) + " nodes"});
    }
  }

  PotreeMetadata metadata_;
  PotreeRecordReader records_;
  std::unique_ptr<ByteSource> hierarchy_, octree_;
  PotreeHierarchyLimits limits_;
  OctreeInfo info_;
  std::vector<OctreeNode> nodes_;
  std::set<std::uint64_t> chunks_read_;
  std::uint64_t total_points_ = 0;  // sum of point_count over nodes_
  std::size_t pending_nodes_ = 0;   // nodes with hierarchy_pending
  // Hierarchy chunks fetched ahead (by offset in hierarchy.bin), for any thread.
  mutable std::mutex fetched_mutex_;
  mutable std::map<std::uint64_t, std::vector<std::byte>> fetched_;
  PotreeReadStats stats_;
  std::atomic<std::uint64_t> hierarchy_bytes_{0};
  mutable std::atomic<std::uint64_t> node_bytes_{0}, nodes_loaded_{0};
};

}  // namespace

std::unique_ptr<Octree> makePotreeOctree(PotreeMetadata metadata, PotreeSources sources) {
  return std::make_unique<PotreeOctree>(std::move(metadata), std::move(sources));
}

const PotreeMetadata* potreeMetadata(const Octree& octree) {
  const auto* potree = dynamic_cast<const PotreeOctree*>(&octree);
  return potree ? &potree->metadata() : nullptr;
}

std::optional<PotreeReadStats> potreeReadStats(const Octree& octree) {
  const auto* potree = dynamic_cast<const PotreeOctree*>(&octree);
  if (!potree) return std::nullopt;
  return potree->readStats();
}

}  // namespace parallax
