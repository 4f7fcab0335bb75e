// Stage 4 of the conversion (convert_stages.h): each chunk's subtree, built in memory with the
// same core as the in-memory octree (subtree_builder.h), written to octree.bin in one piece.
// Several chunks are built at once while they fit in the memory budget together (each build is
// parallel inside too, but its serial parts — reading, the top of the sampling — left a core
// idle); they are written in chunk order, so the output does not depend on the timing.
// The chunk's root stays in memory: the top levels sample from it.
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "core/error.h"
#include "io/mapped_file.h"
#include "lod/convert_stages.h"
#include "lod/subtree_builder.h"

namespace parallax {
namespace {

// The records of `indices`, gathered in order into `out` (indices.size() records).
void gatherRecords(const std::byte* records, std::size_t record_size,
                   std::span<const std::uint32_t> indices, std::byte* out) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, indices.size(), 1 << 15),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        std::memcpy(out + i * record_size,
                                    records + std::size_t(indices[i]) * record_size, record_size);
                      }
                    });
}

}  // namespace

OctreeBinWriter::OctreeBinWriter(const std::filesystem::path& path, std::uint64_t fail_after_bytes,
                                 Open open)
    : path_(path), fail_after_(fail_after_bytes) {
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (open == Open::kCreate ? O_TRUNC : 0);
  fd_ = ::open(path.c_str(), flags, 0644);
  if (fd_ < 0) {
    throw std::runtime_error(path.string() + ": cannot create: " + std::strerror(errno));
  }
  struct stat info {};
  if (open == Open::kExisting && ::fstat(fd_, &info) == 0) size_ = std::uint64_t(info.st_size);
}

OctreeBinWriter::~OctreeBinWriter() {
  if (fd_ >= 0) ::close(fd_);
}

std::uint64_t OctreeBinWriter::append(const std::byte* data, std::size_t size) {
  const std::uint64_t offset = cursor_;
  writeAt(offset, data, size);
  cursor_ += size;
  return offset;
}

void OctreeBinWriter::writeAt(std::uint64_t offset, const std::byte* data, std::size_t size) {
  std::size_t length = size;
  const bool interrupted = fail_after_ > 0 && written_ + size > fail_after_;
  // Write what fits first, so the interruption leaves a half-written file behind.
  if (interrupted) length = std::size_t(fail_after_ - written_);
  std::size_t done = 0;
  while (done < length) {
    const ssize_t n = ::pwrite(fd_, data + done, length - done, off_t(offset + done));
    if (n <= 0) {
      throw std::runtime_error(
          path_.string() + ": cannot write: " + (n == 0 ? "no progress" : std::strerror(errno)));
    }
    done += std::size_t(n);
  }
  if (interrupted) {
    throw std::runtime_error(path_.string() + ": simulated interruption after " +
                             std::to_string(fail_after_) + " bytes");
  }
  written_ += size;
  size_ = std::max(size_, offset + size);
}

void OctreeBinWriter::close() {
  if (fd_ >= 0 && ::close(fd_) != 0) {
    fd_ = -1;
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  }
  fd_ = -1;
}

std::size_t topLevelsSplit(const std::vector<ChunkPlan>& chunks) {
  std::uint64_t total = 0;
  for (const ChunkPlan& chunk : chunks) total += chunk.points;
  std::uint64_t below = 0;
  std::size_t split = 0;
  while (split < chunks.size() && 2 * below < total) below += chunks[split++].points;
  return split;
}

std::uint64_t chunkRecordBytes(const ConvertPlan& plan, std::size_t first, std::size_t last) {
  std::uint64_t points = 0;
  for (std::size_t c = first; c < last; ++c) points += plan.chunks[c].points;
  return points * plan.layout.recordSize();
}

std::uint64_t nonRootBytes(const ConvertPlan& plan, std::size_t first, std::size_t last,
                           const std::vector<ChunkRoot>& roots) {
  std::uint64_t bytes = chunkRecordBytes(plan, first, last);
  for (const ChunkRoot& root : roots) bytes -= root.records.size();
  return bytes;
}

namespace {

// One chunk built and gathered, waiting for its turn to be written.
struct BuiltChunk {
  ByteBuffer records;  // the chunk's records in node order (breadth-first), its root's first
  std::vector<BuiltNode> nodes;
};

BuiltChunk buildOneChunk(const ConvertPlan& plan, std::size_t index, const ChunkSource& source,
                         const OctreeBuildOptions& options, const Sampler& sampler) {
  const std::size_t record = plan.layout.recordSize();
  const ChunkPlan& chunk = plan.chunks[index];
  if (chunk.points == 0) return {.nodes = {BuiltNode{.name = chunk.name}}};
  ChunkRecords spilled = source(index);
  if (spilled.size != chunk.points * record) {
    throw std::runtime_error(spilled.origin + ": expected " +
                             std::to_string(chunk.points * record) + " bytes, found " +
                             std::to_string(spilled.size));
  }
  const std::byte* records = spilled.data;
  const int level = int(chunk.name.size()) - 1;
  const SubtreeFrame frame{.name = chunk.name,
                           .level = level,
                           .box = nodeBox(plan.cube, chunk.name),
                           .spacing = plan.spacing / double(1ull << level)};
  BuiltSubtree built = [&] {
    const Column<Int3> positions = positionsOfRecords(records, chunk.points, record);
    return buildSubtree(positions.span(), plan.quantization, frame, options, sampler);
  }();
  // `order` lists the nodes' points one node after the other, breadth-first: one gather gives
  // the whole chunk in the order octree.bin wants it, written later with a single call.
  BuiltChunk result{.records = ByteBuffer(spilled.size), .nodes = std::move(built.nodes)};
  gatherRecords(records, record, built.order, result.records.data());
  if (!spilled.remove_after.empty()) {
    spilled.mapped.reset();
    std::filesystem::remove(spilled.remove_after);
  }
  return result;
}

// Builds the chunks several at a time and writes them in the placement's order (chunk order up,
// or the reverse down from the end). A chunk is started (in that order) while the chunks started
// and not yet written fit in the budget together, or when none is in flight; whichever thread
// finishes the next chunk to write writes it and starts more. The output is the same whatever
// the timing: the order of writing is fixed, not the order of finishing.
class ChunkScheduler {
 public:
  ChunkScheduler(const ConvertPlan& plan, std::size_t first, std::size_t last,
                 const ChunkSource& source, const OctreeBuildOptions& options,
                 const Sampler& sampler, OctreeBinWriter& octree, ChunkPlacement placement,
                 std::vector<PotreeNodeEntry>& entries, Progress* bar)
      : plan_(plan),
        first_(first),
        last_(last),
        descending_(placement.descending),
        end_at_(placement.at),
        source_(source),
        options_(options),
        sampler_(sampler),
        octree_(octree),
        entries_(entries),
        bar_(bar),
        bytes_per_point_(chunkBuildBytesPerPoint(plan.layout.recordSize())),
        // The batch's quarter of the budget is free once distribute is done.
        budget_(options.memory_bytes / 4 * 3),
        built_(last - first),
        roots_(last - first) {
    if (!descending_) octree_.seek(placement.at);
  }

  std::vector<ChunkRoot> run() {
    {
      std::lock_guard lock(mutex_);
      startMore();
    }
    group_.wait();
    return std::move(roots_);
  }

 private:
  // The chunk written `step`-th.
  std::size_t chunkAt(std::size_t step) const {
    return descending_ ? last_ - 1 - step : first_ + step;
  }

  // Called with mutex_ held.
  void startMore() {
    while (!failed_ && next_start_ < built_.size()) {
      const std::uint64_t cost = plan_.chunks[chunkAt(next_start_)].points * bytes_per_point_;
      if (in_flight_bytes_ > 0 && in_flight_bytes_ + cost > budget_) break;
      in_flight_bytes_ += cost;
      const std::size_t step = next_start_++;
      group_.run([this, step] { buildAndWrite(step); });
    }
  }

  void buildAndWrite(std::size_t step) {
    try {
      throwIfBuildCancelled(options_.cancel);
      BuiltChunk chunk = buildOneChunk(plan_, chunkAt(step), source_, options_, sampler_);
      std::unique_lock lock(mutex_);
      if (failed_) return;
      built_[step] = std::move(chunk);
      if (writing_) return;  // the thread writing now will get to it
      writing_ = true;
      while (next_write_ < built_.size() && built_[next_write_]) {
        BuiltChunk ready = std::move(*built_[next_write_]);
        built_[next_write_].reset();
        const std::size_t written = chunkAt(next_write_);
        lock.unlock();
        roots_[written - first_] = writeChunk(written, ready);
        ready = BuiltChunk{};
        lock.lock();
        in_flight_bytes_ -= plan_.chunks[written].points * bytes_per_point_;
        ++next_write_;
        startMore();
      }
      writing_ = false;
    } catch (...) {
      std::lock_guard lock(mutex_);
      failed_ = true;
      writing_ = false;
      throw;  // task_group::wait rethrows it on the calling thread
    }
  }

  // Writes the chunk's nodes but its root to octree.bin (only the writing thread calls it).
  ChunkRoot writeChunk(std::size_t index, const BuiltChunk& chunk) {
    const std::size_t record = plan_.layout.recordSize();
    const BuiltNode& root = chunk.nodes.front();
    const std::size_t root_bytes = std::size_t(root.count) * record;
    const std::byte* nodes = chunk.records.data() + root_bytes;
    const std::size_t bytes = chunk.records.size() - root_bytes;
    std::uint64_t base = 0;
    if (descending_) {
      end_at_ -= bytes;
      base = end_at_;
      octree_.writeAt(base, nodes, bytes);
    } else {
      base = octree_.append(nodes, bytes);
    }
    for (std::size_t n = 1; n < chunk.nodes.size(); ++n) {
      const BuiltNode& node = chunk.nodes[n];
      entries_.push_back({.name = node.name,
                          .point_count = node.count,
                          .byte_offset = base + (node.first - root.count) * record,
                          .byte_size = std::uint64_t(node.count) * record});
    }
    ChunkRoot kept{.name = plan_.chunks[index].name, .has_children = root.child_mask != 0};
    kept.records.assign(chunk.records.data(), chunk.records.data() + root_bytes);
    if (bar_) bar_->advance(plan_.chunks[index].points);
    return kept;
  }

  const ConvertPlan& plan_;
  const std::size_t first_;
  const std::size_t last_;
  const bool descending_;
  std::uint64_t end_at_;  // descending: where the last chunk written starts
  const ChunkSource& source_;
  const OctreeBuildOptions& options_;
  const Sampler& sampler_;
  OctreeBinWriter& octree_;
  std::vector<PotreeNodeEntry>& entries_;
  Progress* bar_;
  const std::uint64_t bytes_per_point_;
  const std::uint64_t budget_;
  tbb::task_group group_;
  std::mutex mutex_;
  std::size_t next_start_ = 0;  // steps, in the order of writing (chunkAt)
  std::size_t next_write_ = 0;
  std::vector<std::optional<BuiltChunk>> built_;  // finished, not yet written (by step)
  std::vector<ChunkRoot> roots_;                  // from first_
  std::uint64_t in_flight_bytes_ = 0;             // chunks started and not yet written
  bool writing_ = false;
  bool failed_ = false;
};

}  // namespace

std::vector<ChunkRoot> buildChunks(const ConvertPlan& plan, const std::filesystem::path& chunk_dir,
                                   const OctreeBuildOptions& options, const Sampler& sampler,
                                   OctreeBinWriter& octree, std::vector<PotreeNodeEntry>& entries,
                                   const ProgressFactory& progress) {
  std::unique_ptr<Progress> bar = progress ? progress("indexing", plan.points) : nullptr;
  // Mapped, not read: the build reads the records straight from the page cache (a read into a
  // fresh buffer cost a copy and the zeroing of as many new pages). Each spill file goes once
  // its chunk is built.
  const ChunkSource mapped = [&](std::size_t index) {
    ChunkRecords records;
    records.origin = chunkFilePath(chunk_dir, index).string();
    records.mapped = std::make_unique<MappedFile>(chunkFilePath(chunk_dir, index));
    records.data = records.mapped->bytes().data();
    records.size = records.mapped->size();
    records.remove_after = chunkFilePath(chunk_dir, index);
    return records;
  };
  // The lower side up from the start, the upper side down from the end; the gap between is
  // the top levels' (topLevelsSplit).
  const std::size_t split = topLevelsSplit(plan.chunks);
  const std::size_t chunks = plan.chunks.size();
  std::vector<ChunkRoot> roots =
      buildChunkRange(plan, 0, split, mapped, options, sampler, octree,
                      {.descending = false, .at = 0}, entries, bar.get());
  const std::uint64_t lower = nonRootBytes(plan, 0, split, roots);
  std::vector<ChunkRoot> upper = buildChunkRange(
      plan, split, chunks, mapped, options, sampler, octree,
      {.descending = true, .at = chunkRecordBytes(plan, 0, chunks)}, entries, bar.get());
  for (ChunkRoot& root : upper) roots.push_back(std::move(root));
  octree.seek(lower);
  return roots;
}

std::vector<ChunkRoot> buildChunkRange(const ConvertPlan& plan, std::size_t first, std::size_t last,
                                       const ChunkSource& source, const OctreeBuildOptions& options,
                                       const Sampler& sampler, OctreeBinWriter& octree,
                                       ChunkPlacement placement,
                                       std::vector<PotreeNodeEntry>& entries, Progress* bar) {
  assert(first <= last && last <= plan.chunks.size() && "buildChunkRange: chunks of the plan");
  ChunkScheduler scheduler(plan, first, last, source, options, sampler, octree, placement, entries,
                           bar);
  return scheduler.run();
}

}  // namespace parallax
