// The tasks of a distributed conversion (distributed_tasks.h): each stage of convert_stages.h on
// one range or one group, reading and writing the files of distributed_task_files.h.
#include "lod/distributed_tasks.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "core/error.h"
#include "io/partial_output.h"
#include "lod/distributed_task_files.h"
#include "lod/potree_converter.h"
#include "lod/sampler.h"

namespace parallax {
namespace {

using Clock = std::chrono::steady_clock;

// What a build task reports beside its points: whether it wrote straight into octree.bin.
struct BuildSummary {
  std::uint64_t points = 0;
  bool placed = false;
};

// Points read at a time by the scan: the local scan's first guess (convert_count.cpp), before
// the record size is known. Batch sizes change no result, only memory.
std::uint64_t scanBatchPoints(const DistributedPlan& plan) {
  return std::clamp<std::uint64_t>(plan.build.memory_bytes / 8 / 128, 4096, 4u << 20);
}

// A folder of the work directory, which must still exist: a task that outlives its run (its
// driver stopped and removed the work directory) fails instead of creating it again.
void makeTaskDirectory(const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::create_directory(path, error);
  if (error) {
    throw std::runtime_error(path.string() + ": cannot create (" + error.message() +
                             "): is the work directory still there?");
  }
}

std::unique_ptr<PointStream> openRange(const DistributedPlan& plan,
                                       const std::vector<ConvertInput>& inputs, std::size_t range) {
  const InputRange& r = plan.ranges[range];
  const ConvertInput& input = inputs[r.input];
  auto stream = std::make_unique<PointStream>(input.path, input.text_columns,
                                              &plan.inputs[r.input].quantization, &input.filter);
  if (stream->pointCount() != plan.inputs[r.input].points) {
    throw InputError({.file = input.path.string(),
                      .expected = std::to_string(plan.inputs[r.input].points) +
                                  " points, as when the plan was made",
                      .found = std::to_string(stream->pointCount()),
                      .hint = "do not modify the inputs while they are being converted; make "
                              "the plan again"});
  }
  stream->restrictTo(r.first, r.last);
  return stream;
}

std::uint64_t runScan(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                      std::size_t range) {
  auto stream = openRange(plan, inputs, range);
  ScanSummary scan;
  PointCloud batch;
  while (stream->next(batch, scanBatchPoints(plan))) {
    batch.computeBounds();
    scan.bounds.extend(batch.bounds);
    scan.points += batch.count;
  }
  makeTaskDirectory(scanFilePath(plan, range).parent_path());
  writeScanSummary(scanFilePath(plan, range), scan);
  return scan.points;
}

// The ranges' scans merged as the local scan merges its inputs (convert_count.cpp scanInputs).
std::uint64_t runCube(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs) {
  ScanSummary total;
  std::vector<std::uint64_t> input_points(plan.inputs.size(), 0);
  for (std::size_t r = 0; r < plan.ranges.size(); ++r) {
    const ScanSummary scan = readScanSummary(scanFilePath(plan, r));
    total.points += scan.points;
    total.bounds.extend(scan.bounds);
    input_points[plan.ranges[r].input] += scan.points;
  }
  // The layout of every input with a point kept, in input order; with none, positions only.
  PotreeLayout layout;
  bool have_layout = false;
  for (std::size_t i = 0; i < plan.inputs.size(); ++i) {
    if (input_points[i] == 0) continue;
    if (!have_layout) {
      layout = plan.inputs[i].layout;
      have_layout = true;
    } else {
      layout.merge(plan.inputs[i].layout);
    }
  }
  if (!have_layout) layout = PotreeLayout::fromCloud(PointCloud{});
  const bool filtered = std::any_of(inputs.begin(), inputs.end(), [](const ConvertInput& input) {
    return !input.filter.keepsAll();
  });
  if (filtered && total.points == 0 && !inputs.empty()) {
    std::uint64_t file_points = 0;
    for (const PlannedInput& input : plan.inputs) file_points += input.points;
    throw InputError({.file = inputs.front().path.string(),
                      .expected = "at least one point that the class and clip filters keep",
                      .found = "none of " + std::to_string(file_points) + " points",
                      .hint = "check the class list and the clip box against the input's "
                              "classes and bounds (parallax info)"});
  }
  writeCube(cubeFilePath(plan), total, layout);
  return total.points;
}

std::uint64_t runCount(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                       std::size_t range) {
  const ConvertPlan state = loadConvertState(plan, false);
  auto stream = openRange(plan, inputs, range);
  std::vector<std::uint64_t> counts(ConvertPlan::kGridCells, 0);
  countStream(state, *stream, counts, nullptr);
  makeTaskDirectory(countFilePath(plan, range).parent_path());
  writeCounts(countFilePath(plan, range), counts);
  std::uint64_t points = 0;
  for (std::uint64_t count : counts) points += count;
  return points;
}

// The counts summed, the chunks planned as the local count plans them, and consecutive groups
// of chunks of about equal point counts for the build tasks.
std::uint64_t runChunks(const DistributedPlan& plan) {
  ConvertPlan state = loadConvertState(plan, false);
  std::vector<std::uint64_t> counts(ConvertPlan::kGridCells, 0);
  for (std::size_t r = 0; r < plan.ranges.size(); ++r) addCounts(countFilePath(plan, r), counts);
  planChunks(state, std::move(counts));
  ChunkGroups groups{.chunks = state.chunks};
  std::uint64_t total = 0;
  for (const ChunkPlan& chunk : state.chunks) total += chunk.points;
  const std::uint64_t target =
      std::max<std::uint64_t>(1, (total + plan.build_tasks - 1) / plan.build_tasks);
  // No group straddles the split: the groups below it are laid out up from the start of
  // octree.bin, the others down from its end.
  const std::size_t split = topLevelsSplit(state.chunks);
  auto addGroups = [&](std::size_t from, std::size_t to) {
    std::size_t first = from;
    std::uint64_t in_group = 0;
    for (std::size_t c = from; c < to; ++c) {
      in_group += state.chunks[c].points;
      if (in_group >= target || c + 1 == to) {
        groups.groups.emplace_back(first, c + 1);
        first = c + 1;
        in_group = 0;
      }
    }
  };
  addGroups(0, split);
  groups.split = groups.groups.size();
  addGroups(split, state.chunks.size());
  writeChunkGroups(chunksFilePath(plan), groups);
  return total;
}

// Replaces `target` by the finished directory `temp`. Another run of the same task may have
// put an identical one there first: that one is replaced (nothing reads it before this stage
// ends).
void renameDirectory(const std::filesystem::path& temp, const std::filesystem::path& target) {
  std::error_code error;
  std::filesystem::rename(temp, target, error);
  if (!error) return;
  std::filesystem::remove_all(target);
  std::filesystem::rename(temp, target);
}

std::uint64_t runDistribute(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                            std::size_t range) {
  ConvertPlan state = loadConvertState(plan, true);
  auto stream = openRange(plan, inputs, range);
  const std::filesystem::path target = shardDirPath(plan, range);
  makeTaskDirectory(target.parent_path());
  const std::filesystem::path temp = temporaryPathFor(target);
  std::filesystem::remove_all(temp);
  std::uint64_t points = 0;
  try {
    const std::vector<std::uint64_t> delivered =
        distributeStream(state, *stream, inputs[plan.ranges[range].input].path, temp, nullptr);
    for (std::uint64_t n : delivered) points += n;
    // Beside the shards, not among them: the driver removes the shards once the builds ran.
    makeTaskDirectory(statsFilePath(plan, range).parent_path());
    writeStats(statsFilePath(plan, range), state.stats);
    renameDirectory(temp, target);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove_all(temp, ignored);
    throw;
  }
  return points;
}

// A chunk's records from the shards of every range, in range order: the order the local build
// spills them in.
ChunkRecords readShards(const DistributedPlan& plan, const ConvertPlan& state, std::size_t chunk) {
  const std::uint64_t size = state.chunks[chunk].points * state.layout.recordSize();
  ChunkRecords records;
  records.owned = ByteBuffer(std::size_t(size));
  records.data = records.owned.data();
  records.size = size;
  records.origin =
      "the shards of chunk " + std::to_string(chunk) + " in " + (plan.work_dir / "shards").string();
  std::uint64_t filled = 0;
  for (std::size_t r = 0; r < plan.ranges.size(); ++r) {
    const std::filesystem::path path = chunkFilePath(shardDirPath(plan, r), chunk);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT) continue;  // the range has no point in this chunk
      throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
    }
    struct stat info {};
    if (::fstat(fd, &info) != 0 || std::uint64_t(info.st_size) > size - filled) {
      ::close(fd);
      throw std::runtime_error(path.string() + ": more records than the count of chunk " +
                               state.chunks[chunk].name + " (or unreadable)");
    }
    std::uint64_t at = 0;
    while (at < std::uint64_t(info.st_size)) {
      const ssize_t n = ::pread(fd, records.owned.data() + filled,
                                std::size_t(std::uint64_t(info.st_size) - at), off_t(at));
      if (n <= 0) {
        const int error = errno;
        ::close(fd);
        throw std::runtime_error(path.string() + ": cannot read: " +
                                 (n == 0 ? "shorter than its size" : std::strerror(error)));
      }
      filled += std::uint64_t(n);
      at += std::uint64_t(n);
    }
    ::close(fd);
  }
  // A short total is reported by the build with the expected and found sizes.
  records.size = filled;
  return records;
}

// The size of octree.bin: every chunk's records (topLevelsSplit).
std::uint64_t octreeBytes(const ConvertPlan& state) {
  return chunkRecordBytes(state, 0, state.chunks.size());
}

// The error of nodes files whose parts add up to more than octree.bin holds (damaged files).
[[noreturn]] void partsOverflow(const DistributedPlan& plan, std::uint64_t octree_bytes) {
  throw std::runtime_error((plan.work_dir / "build").string() +
                           ": the groups' parts take more than the chunks' " +
                           std::to_string(octree_bytes) + " bytes; run the builds again");
}

// Where group `group` writes in the assembled octree.bin, if the builds it depends on are done:
// below the split, where the parts of the groups before it end (its first byte); from the split
// on, where those after it start (its last byte's end). Unknown while one of them is missing.
std::optional<std::uint64_t> knownPlace(const DistributedPlan& plan, const ChunkGroups& groups,
                                        std::uint64_t octree_bytes, std::size_t group) {
  const bool upper = group >= groups.split;
  const std::size_t from = upper ? group + 1 : 0, to = upper ? groups.groups.size() : group;
  std::uint64_t bytes = 0;
  for (std::size_t g = from; g < to; ++g) {
    std::error_code error;
    if (!std::filesystem::exists(groupNodesPath(plan, g), error)) return std::nullopt;
    // Checked before it is added, so no sum of damaged sizes can wrap around.
    const std::uint64_t part = readGroupPartHead(groupNodesPath(plan, g)).part_bytes;
    if (part > octree_bytes - bytes) partsOverflow(plan, octree_bytes);
    bytes += part;
  }
  return upper ? octree_bytes - bytes : bytes;
}

// The chunks of one group built, their nodes written straight into the assembled octree.bin when
// the group's place there is known (knownPlace: with two workers taking the groups from both
// ends, always), into a part file for the place stage to copy otherwise.
BuildSummary runBuild(const DistributedPlan& plan, std::size_t group) {
  const ConvertPlan state = loadConvertState(plan, true);
  const ChunkGroups groups = readChunkGroups(chunksFilePath(plan));
  const auto [first, last] = groups.groups[group];
  const auto sampler = makeSampler(plan.build.sampling);
  const std::filesystem::path part_path = groupPartPath(plan, group);
  makeTaskDirectory(part_path.parent_path());
  const ChunkSource shards = [&](std::size_t chunk) { return readShards(plan, state, chunk); };
  GroupNodes nodes;
  const std::optional<std::uint64_t> place = knownPlace(plan, groups, octreeBytes(state), group);
  if (place) {
    const bool upper = group >= groups.split;
    OctreeBinWriter octree(assembledOctreePath(plan), 0, OctreeBinWriter::Open::kExisting);
    nodes.roots = buildChunkRange(state, first, last, shards, plan.build, *sampler, octree,
                                  {.descending = upper, .at = *place}, nodes.entries, nullptr);
    octree.close();
    nodes.part_bytes = nonRootBytes(state, first, last, nodes.roots);
    nodes.placed = true;
    // The nodes file states offsets into the part, wherever it was written.
    const std::uint64_t start = upper ? *place - nodes.part_bytes : *place;
    for (PotreeNodeEntry& entry : nodes.entries) entry.byte_offset -= start;
    // A part file an earlier try left (its place was not known then) stays: a try of the same
    // build running at once (Dask runs a task again when it thinks its worker lost) may be about
    // to state it in the nodes file. Which one counts is what the last nodes file written says.
  } else {
    const std::filesystem::path temp = temporaryPathFor(part_path);
    try {
      OctreeBinWriter part(temp, 0);
      nodes.roots = buildChunkRange(state, first, last, shards, plan.build, *sampler, part,
                                    {.descending = false, .at = 0}, nodes.entries, nullptr);
      part.close();
      nodes.part_bytes = part.size();
      std::filesystem::rename(temp, part_path);
    } catch (...) {
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw;
    }
  }
  // Written after the part: the place and finish tasks trust a part only with its nodes file,
  // which states the part's size.
  std::filesystem::remove(groupPlacedPath(plan, group));
  writeGroupNodes(groupNodesPath(plan, group), nodes);
  BuildSummary summary{.placed = nodes.placed};
  for (std::size_t c = first; c < last; ++c) summary.points += state.chunks[c].points;
  return summary;
}

// Copies `length` bytes of `from` to `to_fd` at `offset` (copy_file_range: in the kernel, or
// sharing blocks where the file system can; read and written by hand where it cannot).
void copyInto(const std::filesystem::path& from, std::uint64_t length, int to_fd,
              std::uint64_t offset, const std::filesystem::path& to) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw std::runtime_error(from.string() + ": cannot open: " + std::strerror(errno));
  std::uint64_t done = 0;
  std::vector<char> buffer;
  while (done < length) {
    ssize_t n = -1;
    if (buffer.empty()) {
      loff_t in_at = loff_t(done), out_at = loff_t(offset + done);
      n = ::copy_file_range(in, &in_at, to_fd, &out_at, std::size_t(length - done), 0);
      if (n < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP)) {
        buffer.resize(std::size_t(4) << 20);
        continue;
      }
    } else {
      n = ::pread(in, buffer.data(), std::min<std::uint64_t>(buffer.size(), length - done),
                  off_t(done));
      if (n > 0 && ::pwrite(to_fd, buffer.data(), std::size_t(n), off_t(offset + done)) != n) {
        n = -1;
      }
    }
    if (n <= 0) {
      const int error = errno;
      ::close(in);
      throw std::runtime_error(
          to.string() + ": cannot copy " + from.string() +
          " into it: " + (n == 0 ? "the file is shorter than its size" : std::strerror(error)));
    }
    done += std::uint64_t(n);
  }
  ::close(in);
}

// Where each group's part starts in the assembled octree.bin (from the sizes its build stated:
// up from the start below the split, down from the end from it on), and the gap between the two
// sides that the top levels fill.
struct PartPlaces {
  std::vector<std::uint64_t> start;
  std::vector<GroupPartHead> parts;
  std::uint64_t gap_begin = 0;
  std::uint64_t gap_end = 0;
};

PartPlaces partPlaces(const DistributedPlan& plan, const ChunkGroups& groups,
                      std::uint64_t octree_bytes) {
  PartPlaces places;
  const std::size_t count = groups.groups.size();
  for (std::size_t g = 0; g < count; ++g) {
    places.parts.push_back(readGroupPartHead(groupNodesPath(plan, g)));
  }
  places.start.resize(count);
  // Each part must fit in what is left between the two sides (damaged nodes files may say
  // otherwise): checked before it is placed, so no sum can wrap around.
  std::uint64_t at = 0, end = octree_bytes;
  for (std::size_t g = 0; g < groups.split; ++g) {
    if (places.parts[g].part_bytes > end - at) partsOverflow(plan, octree_bytes);
    places.start[g] = at;
    at += places.parts[g].part_bytes;
  }
  for (std::size_t g = count; g-- > groups.split;) {
    if (places.parts[g].part_bytes > end - at) partsOverflow(plan, octree_bytes);
    end -= places.parts[g].part_bytes;
    places.start[g] = end;
  }
  places.gap_begin = at;
  places.gap_end = end;
  return places;
}

// The part file of `group` copied to its place in the work directory's octree.bin, then marked
// as placed. Written at a fixed offset, a copy run again writes the same bytes.
void copyPart(const DistributedPlan& plan, std::size_t group, const PartPlaces& places) {
  const std::filesystem::path part = groupPartPath(plan, group);
  const std::uint64_t bytes = places.parts[group].part_bytes;
  std::error_code error;
  const std::uint64_t size = std::filesystem::file_size(part, error);
  if (error || size != bytes) {
    throw std::runtime_error(part.string() + ": expected " + std::to_string(bytes) + " bytes (" +
                             groupNodesPath(plan, group).string() + "), found " +
                             (error ? error.message() : std::to_string(size)) + "; run build " +
                             std::to_string(group) + " again");
  }
  const std::filesystem::path assembled = assembledOctreePath(plan);
  const int fd = ::open(assembled.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error(assembled.string() + ": cannot open: " + std::strerror(errno));
  }
  try {
    copyInto(part, bytes, fd, places.start[group], assembled);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) {
    throw std::runtime_error(assembled.string() + ": cannot write: " + std::strerror(errno));
  }
  writeFileAtomically(groupPlacedPath(plan, group), "");
}

bool partInPlace(const DistributedPlan& plan, const PartPlaces& places, std::size_t group) {
  std::error_code error;
  return places.parts[group].placed || std::filesystem::exists(groupPlacedPath(plan, group), error);
}

// The part of a group whose build could not write it in place, copied there: the places are
// known once every build ran, so the copies run side by side instead of one after the other in
// the finish task (at 10^11 points, hours of copying on one machine). Nothing to do for a group
// its build placed.
std::uint64_t runPlace(const DistributedPlan& plan, std::size_t group) {
  const ConvertPlan state = loadConvertState(plan, true);
  const ChunkGroups groups = readChunkGroups(chunksFilePath(plan));
  const PartPlaces places = partPlaces(plan, groups, octreeBytes(state));
  if (places.parts[group].placed) return 0;
  copyPart(plan, group, places);
  return places.parts[group].part_bytes;
}

// The parts not yet in place copied (when the place stage did not run), the top levels written
// into the gap between the two sides of the assembled octree.bin, then hierarchy.bin and
// metadata.json in a partial directory renamed to the output, octree.bin moved into it (a
// rename: the work directory is on the same file system by default). potree_converter.cpp does
// the same locally.
std::uint64_t runFinish(const DistributedPlan& plan) {
  ConvertPlan state = loadConvertState(plan, true);
  for (std::size_t r = 0; r < plan.ranges.size(); ++r) {
    mergeStats(statsFilePath(plan, r), state.stats);
  }
  const ChunkGroups groups = readChunkGroups(chunksFilePath(plan));
  const std::uint64_t octree_bytes = octreeBytes(state);
  const PartPlaces places = partPlaces(plan, groups, octree_bytes);
  const std::filesystem::path assembled = assembledOctreePath(plan);
  std::error_code error;
  const bool existed = std::filesystem::exists(assembled, error);
  for (std::size_t g = 0; g < groups.groups.size(); ++g) {
    if (!partInPlace(plan, places, g)) {
      copyPart(plan, g, places);
    } else if (!existed) {
      // An earlier finish moved the file out and then failed: what the builds placed is gone.
      throw std::runtime_error(assembled.string() + ": missing, with the part of build " +
                               std::to_string(g) + " in it; run the builds again");
    }
  }
  std::vector<PotreeNodeEntry> entries;
  std::vector<ChunkRoot> roots;
  for (std::size_t g = 0; g < groups.groups.size(); ++g) {
    GroupNodes nodes = readGroupNodes(groupNodesPath(plan, g));
    for (PotreeNodeEntry& entry : nodes.entries) {
      entry.byte_offset += places.start[g];
      entries.push_back(std::move(entry));
    }
    for (ChunkRoot& root : nodes.roots) roots.push_back(std::move(root));
  }
  if (roots.size() != state.chunks.size()) {
    throw std::runtime_error(chunksFilePath(plan).string() + ": " +
                             std::to_string(state.chunks.size()) + " chunks, the builds gave " +
                             std::to_string(roots.size()));
  }
  {
    OctreeBinWriter octree(assembled, 0, OctreeBinWriter::Open::kExisting);
    octree.seek(places.gap_begin);
    const auto sampler = makeSampler(plan.build.sampling);
    buildTopLevels(state, roots, *sampler, octree, entries);
    if (octree.cursor() != places.gap_end) {
      throw std::runtime_error(assembled.string() + ": the top levels took " +
                               std::to_string(octree.cursor() - places.gap_begin) +
                               " bytes, the gap between the parts is " +
                               std::to_string(places.gap_end - places.gap_begin) +
                               "; run the builds again");
    }
    octree.close();
  }
  // Cut back to the records (an earlier run may have left a longer file).
  std::filesystem::resize_file(assembled, octree_bytes);
  if (entries.empty()) entries.push_back({.name = "r"});  // an empty input: a root, no points

  const std::filesystem::path target = plan.output;
  checkPotreeOutput(target);
  std::filesystem::create_directories(target.parent_path());
  removeStalePartialOutputs(target);
  TemporaryDirectory temp(partialOutputPath(target));
  const std::filesystem::path octree_path = temp.path() / "octree.bin";
  std::filesystem::rename(assembled, octree_path);
  try {
    writePotreeIndex(state, entries, target.filename().string(), plan.projection, temp, target);
  } catch (...) {
    // Back where a finish run again finds it.
    std::error_code ignored;
    std::filesystem::rename(octree_path, assembled, ignored);
    throw;
  }
  return state.points;
}

}  // namespace

const std::vector<std::string_view>& distributedStages() {
  static const std::vector<std::string_view> stages = {"scan",       "cube",  "count", "chunks",
                                                       "distribute", "build", "place", "finish"};
  return stages;
}

std::size_t distributedStageParts(const DistributedPlan& plan, std::string_view stage) {
  if (stage == "scan" || stage == "count" || stage == "distribute") return plan.ranges.size();
  if (stage == "build" || stage == "place") {
    return readChunkGroups(chunksFilePath(plan)).groups.size();
  }
  return 1;
}

std::string runDistributedTask(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                               std::string_view stage, std::size_t part) {
  const auto& stages = distributedStages();
  if (std::find(stages.begin(), stages.end(), stage) == stages.end()) {
    throw std::invalid_argument("convert-task: unknown stage '" + std::string(stage) +
                                "' (scan, cube, count, chunks, distribute, build, place, finish)");
  }
  if (inputs.size() != plan.inputs.size()) {
    throw std::invalid_argument("convert-task: the inputs are not the plan's");
  }
  const std::size_t parts = distributedStageParts(plan, stage);
  if (part >= parts) {
    throw std::invalid_argument("convert-task " + std::string(stage) + ": part " +
                                std::to_string(part) + " of " + std::to_string(parts) +
                                " (parts are 0 to " + std::to_string(parts - 1) + ")");
  }
  const auto start = Clock::now();
  std::uint64_t points = 0;
  if (stage == "scan") points = runScan(plan, inputs, part);
  if (stage == "cube") points = runCube(plan, inputs);
  if (stage == "count") points = runCount(plan, inputs, part);
  if (stage == "chunks") points = runChunks(plan);
  if (stage == "distribute") points = runDistribute(plan, inputs, part);
  std::string extra;
  if (stage == "build") {
    const BuildSummary build = runBuild(plan, part);
    points = build.points;
    extra = std::string(", \"placed\": ") + (build.placed ? "true" : "false");
  }
  if (stage == "place") points = runPlace(plan, part);
  if (stage == "finish") points = runFinish(plan);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return "{\"stage\": \"" + std::string(stage) + "\", \"part\": " + std::to_string(part) +
         ", \"parts\": " + std::to_string(parts) + ", \"points\": " + std::to_string(points) +
         ", \"seconds\": " + std::to_string(seconds) + extra + "}";
}

}  // namespace parallax
