// The files the tasks of a distributed conversion hand each other (distributed_plan.h lists
// them), and the conversion state (ConvertPlan) rebuilt from them in every task.
//
// Binary files start with an 8-byte tag and are checked against their own sizes when read: a
// damaged or truncated file is a std::runtime_error naming it, never a wrong octree. They are
// written on the machine that reads them back or on one like it (native little endian: every
// platform Parallax builds for).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "lod/convert_stages.h"
#include "lod/distributed_plan.h"
#include "lod/potree_hierarchy_writer.h"

namespace parallax {

std::filesystem::path scanFilePath(const DistributedPlan& plan, std::size_t range);
std::filesystem::path cubeFilePath(const DistributedPlan& plan);
std::filesystem::path countFilePath(const DistributedPlan& plan, std::size_t range);
std::filesystem::path chunksFilePath(const DistributedPlan& plan);
std::filesystem::path shardDirPath(const DistributedPlan& plan, std::size_t range);
std::filesystem::path statsFilePath(const DistributedPlan& plan, std::size_t range);
std::filesystem::path groupPartPath(const DistributedPlan& plan, std::size_t group);
std::filesystem::path groupNodesPath(const DistributedPlan& plan, std::size_t group);
// octree.bin of the chunks, assembled from the groups' parts by the place tasks.
std::filesystem::path assembledOctreePath(const DistributedPlan& plan);

// Removes the task files an earlier run left in `work_dir` (only the names the tasks write:
// a work directory given by hand may hold other files), so that a new plan's tasks never read
// an old run's.
void clearTaskFiles(const std::filesystem::path& work_dir);

// Non-empty count grid cells of one range.
void writeCounts(const std::filesystem::path& path, const std::vector<std::uint64_t>& counts);
// Adds the counts of `path` to `counts` (ConvertPlan::kGridCells entries).
void addCounts(const std::filesystem::path& path, std::vector<std::uint64_t>& counts);

void writeStats(const std::filesystem::path& path, const AttributeStats& stats);
// Widens `stats` by the file's (the same number of attributes).
void mergeStats(const std::filesystem::path& path, AttributeStats& stats);

// What a build task hands the finish task beside its part of octree.bin: the part's size, the
// nodes in it (offsets into the part) and the chunks' roots. `placed`: the build wrote its part
// straight into the assembled octree.bin (at its place, which it knew), not into a part file.
struct GroupNodes {
  std::uint64_t part_bytes = 0;
  bool placed = false;
  std::vector<PotreeNodeEntry> entries;
  std::vector<ChunkRoot> roots;
};
void writeGroupNodes(const std::filesystem::path& path, const GroupNodes& nodes);
GroupNodes readGroupNodes(const std::filesystem::path& path);
// part_bytes and placed alone (the first bytes of the file).
struct GroupPartHead {
  std::uint64_t part_bytes = 0;
  bool placed = false;
};
GroupPartHead readGroupPartHead(const std::filesystem::path& path);
// Marks the part of `group` as copied to its place by the place stage (an empty file beside it).
std::filesystem::path groupPlacedPath(const DistributedPlan& plan, std::size_t group);

// The chunks (and their groups of consecutive chunks, [first, last) each) of chunks.json. The
// groups from `split` on hold the chunks from topLevelsSplit on: their parts are laid out down
// from the end of octree.bin, the others up from its start.
struct ChunkGroups {
  std::vector<ChunkPlan> chunks;
  std::vector<std::pair<std::size_t, std::size_t>> groups;
  std::size_t split = 0;
};
void writeChunkGroups(const std::filesystem::path& path, const ChunkGroups& chunks);
ChunkGroups readChunkGroups(const std::filesystem::path& path);

// One range's scan (scan/range_R.json) and the merged one (cube.json): points, bounds, and for
// the cube the merged layout.
struct ScanSummary {
  std::uint64_t points = 0;
  Bounds3 bounds;
};
void writeScanSummary(const std::filesystem::path& path, const ScanSummary& scan);
ScanSummary readScanSummary(const std::filesystem::path& path);
void writeCube(const std::filesystem::path& path, const ScanSummary& scan,
               const PotreeLayout& layout);

// The conversion state after the scan (cube.json; the cube and everything derived from it
// recomputed as the local scan does), and with `with_chunks` after the count (chunks.json; the
// cell-to-chunk map rebuilt from the chunks' names). Stats start empty.
ConvertPlan loadConvertState(const DistributedPlan& plan, bool with_chunks);

}  // namespace parallax
