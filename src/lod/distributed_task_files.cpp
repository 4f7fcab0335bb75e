// The task files of a distributed conversion (distributed_task_files.h).
#include "lod/distributed_task_files.h"

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>

namespace parallax {
namespace {

constexpr std::string_view kCountsTag = "PLXCNT1\n";
constexpr std::string_view kStatsTag = "PLXSTA1\n";
constexpr std::string_view kGroupTag = "PLXGRP2\n";

std::string numbered(const char* prefix, std::size_t index) {
  return prefix + std::to_string(index);
}

class ByteWriter {
 public:
  explicit ByteWriter(std::string_view tag) : bytes_(tag) {}
  template <typename T>
  void put(T value) {
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  void putBytes(const void* data, std::size_t size) {
    bytes_.append(static_cast<const char*>(data), size);
  }
  void putName(const std::string& name) {
    put(std::uint32_t(name.size()));
    bytes_.append(name);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

// Reads what ByteWriter wrote; anything short or out of place throws, naming the file.
class ByteReader {
 public:
  ByteReader(std::filesystem::path path, std::string_view tag)
      : path_(std::move(path)), bytes_(readWholeFile(path_)) {
    if (bytes_.compare(0, tag.size(), tag) != 0) fail("another tag");
    at_ = tag.size();
  }
  template <typename T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  const char* take(std::uint64_t size) {
    if (size > bytes_.size() - at_) fail("the file ends early");
    const char* data = bytes_.data() + at_;
    at_ += std::size_t(size);
    return data;
  }
  std::string getName() {
    const auto size = get<std::uint32_t>();
    return std::string(take(size), size);
  }
  // A count of items of at least `item_bytes` each, checked against the bytes left.
  std::uint64_t getCount(std::size_t item_bytes) {
    const auto count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / item_bytes) fail("a count larger than the file");
    return count;
  }
  void end() {
    if (at_ != bytes_.size()) fail("bytes after the end");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_.string() + ": a damaged task file (" + what +
                             "); run the task that writes it again");
  }

 private:
  std::filesystem::path path_;
  std::string bytes_;
  std::size_t at_ = 0;
};

nlohmann::json boundsJson(const Bounds3& bounds) {
  if (bounds.empty()) return nullptr;
  return {{"min", bounds.min}, {"max", bounds.max}};
}

Bounds3 boundsFrom(const nlohmann::json& json) {
  Bounds3 bounds;
  if (json.is_null()) return bounds;
  bounds.min = json.at("min").get<std::array<double, 3>>();
  bounds.max = json.at("max").get<std::array<double, 3>>();
  return bounds;
}

nlohmann::json parseTaskJson(const std::filesystem::path& path) {
  try {
    return nlohmann::json::parse(readWholeFile(path));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": a damaged task file (" + e.what() +
                             "); run the task that writes it again");
  }
}

}  // namespace

std::filesystem::path scanFilePath(const DistributedPlan& plan, std::size_t range) {
  return plan.work_dir / "scan" / (numbered("range_", range) + ".json");
}
std::filesystem::path cubeFilePath(const DistributedPlan& plan) {
  return plan.work_dir / "cube.json";
}
std::filesystem::path countFilePath(const DistributedPlan& plan, std::size_t range) {
  return plan.work_dir / "count" / (numbered("range_", range) + ".bin");
}
std::filesystem::path chunksFilePath(const DistributedPlan& plan) {
  return plan.work_dir / "chunks.json";
}
std::filesystem::path shardDirPath(const DistributedPlan& plan, std::size_t range) {
  return plan.work_dir / "shards" / numbered("range_", range);
}
std::filesystem::path statsFilePath(const DistributedPlan& plan, std::size_t range) {
  return plan.work_dir / "stats" / (numbered("range_", range) + ".bin");
}
std::filesystem::path groupPartPath(const DistributedPlan& plan, std::size_t group) {
  return plan.work_dir / "build" / (numbered("group_", group) + ".octree.bin");
}
std::filesystem::path groupNodesPath(const DistributedPlan& plan, std::size_t group) {
  return plan.work_dir / "build" / (numbered("group_", group) + ".nodes.bin");
}
std::filesystem::path groupPlacedPath(const DistributedPlan& plan, std::size_t group) {
  return plan.work_dir / "build" / (numbered("group_", group) + ".placed");
}

void clearTaskFiles(const std::filesystem::path& work_dir) {
  for (const char* name :
       {"scan", "cube.json", "count", "chunks.json", "shards", "stats", "build"}) {
    std::filesystem::remove_all(work_dir / name);
  }
}

std::filesystem::path assembledOctreePath(const DistributedPlan& plan) {
  return plan.work_dir / "build" / "octree.bin";
}

GroupPartHead readGroupPartHead(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char head[17];
  if (!in.read(head, sizeof head) || std::string_view(head, 8) != kGroupTag) {
    throw std::runtime_error(path.string() +
                             ": a damaged or missing task file; run the build "
                             "that writes it again");
  }
  GroupPartHead result;
  std::memcpy(&result.part_bytes, head + 8, sizeof result.part_bytes);
  result.placed = head[16] != 0;
  return result;
}

void writeCounts(const std::filesystem::path& path, const std::vector<std::uint64_t>& counts) {
  std::uint64_t cells = 0;
  for (std::uint64_t count : counts) cells += count > 0;
  ByteWriter out(kCountsTag);
  out.put(cells);
  for (std::size_t c = 0; c < counts.size(); ++c) {
    if (counts[c] == 0) continue;
    out.put(std::uint32_t(c));
    out.put(counts[c]);
  }
  writeFileAtomically(path, out.bytes());
}

void addCounts(const std::filesystem::path& path, std::vector<std::uint64_t>& counts) {
  ByteReader in(path, kCountsTag);
  const std::uint64_t cells = in.getCount(12);
  for (std::uint64_t i = 0; i < cells; ++i) {
    const auto cell = in.get<std::uint32_t>();
    if (cell >= counts.size()) in.fail("a cell outside the count grid");
    counts[cell] += in.get<std::uint64_t>();
  }
  in.end();
}

void writeStats(const std::filesystem::path& path, const AttributeStats& stats) {
  ByteWriter out(kStatsTag);
  out.put(std::uint64_t(stats.min.size()));
  for (std::size_t a = 0; a < stats.min.size(); ++a) {
    for (double v : stats.min[a]) out.put(v);
    for (double v : stats.max[a]) out.put(v);
  }
  writeFileAtomically(path, out.bytes());
}

void mergeStats(const std::filesystem::path& path, AttributeStats& stats) {
  ByteReader in(path, kStatsTag);
  const std::uint64_t attributes = in.getCount(48);
  if (attributes != stats.min.size()) in.fail("another number of attributes");
  AttributeStats range = stats;
  for (std::size_t a = 0; a < attributes; ++a) {
    for (double& v : range.min[a]) v = in.get<double>();
    for (double& v : range.max[a]) v = in.get<double>();
  }
  in.end();
  stats.merge(range);
}

void writeGroupNodes(const std::filesystem::path& path, const GroupNodes& nodes) {
  ByteWriter out(kGroupTag);
  out.put(nodes.part_bytes);
  out.put(std::uint8_t(nodes.placed));
  out.put(std::uint64_t(nodes.entries.size()));
  for (const PotreeNodeEntry& entry : nodes.entries) {
    out.putName(entry.name);
    out.put(entry.point_count);
    out.put(entry.byte_offset);
    out.put(entry.byte_size);
  }
  out.put(std::uint64_t(nodes.roots.size()));
  for (const ChunkRoot& root : nodes.roots) {
    out.putName(root.name);
    out.put(std::uint8_t(root.has_children));
    out.put(std::uint64_t(root.records.size()));
    out.putBytes(root.records.data(), root.records.size());
  }
  writeFileAtomically(path, out.bytes());
}

GroupNodes readGroupNodes(const std::filesystem::path& path) {
  ByteReader in(path, kGroupTag);
  GroupNodes nodes;
  nodes.part_bytes = in.get<std::uint64_t>();
  nodes.placed = in.get<std::uint8_t>() != 0;
  const std::uint64_t entries = in.getCount(24);
  for (std::uint64_t i = 0; i < entries; ++i) {
    PotreeNodeEntry entry;
    entry.name = in.getName();
    entry.point_count = in.get<std::uint32_t>();
    entry.byte_offset = in.get<std::uint64_t>();
    entry.byte_size = in.get<std::uint64_t>();
    if (entry.byte_offset > nodes.part_bytes ||
        entry.byte_size > nodes.part_bytes - entry.byte_offset) {
      in.fail("a node outside its part of octree.bin");
    }
    nodes.entries.push_back(std::move(entry));
  }
  const std::uint64_t roots = in.getCount(13);
  for (std::uint64_t i = 0; i < roots; ++i) {
    ChunkRoot root;
    root.name = in.getName();
    root.has_children = in.get<std::uint8_t>() != 0;
    const auto size = in.get<std::uint64_t>();
    const char* data = in.take(size);
    root.records.resize(std::size_t(size));
    std::memcpy(root.records.data(), data, std::size_t(size));
    nodes.roots.push_back(std::move(root));
  }
  in.end();
  return nodes;
}

void writeChunkGroups(const std::filesystem::path& path, const ChunkGroups& chunks) {
  nlohmann::json list = nlohmann::json::array();
  for (const ChunkPlan& chunk : chunks.chunks) list.push_back({chunk.name, chunk.points});
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& [first, last] : chunks.groups) groups.push_back({first, last});
  const nlohmann::json json = {{"chunks", list}, {"groups", groups}, {"split", chunks.split}};
  writeFileAtomically(path, json.dump() + "\n");
}

ChunkGroups readChunkGroups(const std::filesystem::path& path) {
  const nlohmann::json json = parseTaskJson(path);
  ChunkGroups result;
  try {
    for (const nlohmann::json& chunk : json.at("chunks")) {
      result.chunks.push_back({chunk.at(0).get<std::string>(), jsonCount(chunk.at(1))});
    }
    for (const nlohmann::json& group : json.at("groups")) {
      result.groups.emplace_back(jsonCount(group.at(0)), jsonCount(group.at(1)));
    }
    result.split = std::size_t(jsonCount(json.at("split")));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": a damaged task file (" + e.what() + ")");
  }
  for (const ChunkPlan& chunk : result.chunks) {
    const bool digits = chunk.name.find_first_not_of("01234567", 1) == std::string::npos;
    if (chunk.name.empty() || chunk.name[0] != 'r' || !digits ||
        chunk.name.size() > std::size_t(ConvertPlan::kGridLevel) + 1) {
      throw std::runtime_error(path.string() + ": a damaged task file (chunk name '" + chunk.name +
                               "')");
    }
  }
  for (const auto& [first, last] : result.groups) {
    if (first > last || last > result.chunks.size()) {
      throw std::runtime_error(path.string() + ": a damaged task file (a group of no chunks)");
    }
  }
  if (result.split > result.groups.size()) {
    throw std::runtime_error(path.string() + ": a damaged task file (split past the groups)");
  }
  return result;
}

void writeScanSummary(const std::filesystem::path& path, const ScanSummary& scan) {
  const nlohmann::json json = {{"points", scan.points}, {"bounds", boundsJson(scan.bounds)}};
  writeFileAtomically(path, json.dump() + "\n");
}

ScanSummary readScanSummary(const std::filesystem::path& path) {
  const nlohmann::json json = parseTaskJson(path);
  try {
    return {.points = jsonCount(json.at("points")), .bounds = boundsFrom(json.at("bounds"))};
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": a damaged task file (" + e.what() + ")");
  }
}

void writeCube(const std::filesystem::path& path, const ScanSummary& scan,
               const PotreeLayout& layout) {
  const nlohmann::json json = {{"points", scan.points},
                               {"bounds", boundsJson(scan.bounds)},
                               {"layout", layout.toPlanJson()}};
  writeFileAtomically(path, json.dump(2) + "\n");
}

ConvertPlan loadConvertState(const DistributedPlan& plan, bool with_chunks) {
  const std::filesystem::path cube_path = cubeFilePath(plan);
  const nlohmann::json cube = parseTaskJson(cube_path);
  ConvertPlan state;
  try {
    state.points = jsonCount(cube.at("points"));
    state.bounds = boundsFrom(cube.at("bounds"));
    state.layout = PotreeLayout::fromPlanJson(cube.at("layout"), cube_path.string());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(cube_path.string() + ": a damaged task file (" + e.what() + ")");
  }
  for (const PlannedInput& input : plan.inputs) {
    state.input_quantizations.push_back(input.quantization);
  }
  finishScan(state, plan.build);
  if (!with_chunks) return state;

  state.chunks = readChunkGroups(chunksFilePath(plan)).chunks;
  // The cells under each chunk, as planChunks marked them (convert_count.cpp).
  state.cell_chunk.assign(ConvertPlan::kGridCells, -1);
  for (std::size_t id = 0; id < state.chunks.size(); ++id) {
    const std::string& name = state.chunks[id].name;
    std::size_t x = 0, y = 0, z = 0;
    for (std::size_t i = 1; i < name.size(); ++i) {
      const int octant = name[i] - '0';
      x = 2 * x + ((octant >> 2) & 1);
      y = 2 * y + ((octant >> 1) & 1);
      z = 2 * z + (octant & 1);
    }
    const int level = int(name.size()) - 1;
    const std::size_t span = std::size_t(1) << (ConvertPlan::kGridLevel - level);
    for (std::size_t cx = x * span; cx < (x + 1) * span; ++cx)
      for (std::size_t cy = y * span; cy < (y + 1) * span; ++cy)
        for (std::size_t cz = z * span; cz < (z + 1) * span; ++cz)
          state.cell_chunk[ConvertPlan::cellIndex(cx, cy, cz)] = std::int32_t(id);
  }
  return state;
}

}  // namespace parallax
