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
                                 bool keep_existing)
    : path_(path), fail_after_(fail_after_bytes) {
  file_ = std::fopen(path.c_str(), keep_existing ? "ab" : "wb");
  if (!file_) throw std::runtime_error(path.string() + ": cannot create: " + std::strerror(errno));
  if (keep_existing) size_ = std::filesystem::file_size(path);
}

OctreeBinWriter::~OctreeBinWriter() {
  if (file_) std::fclose(file_);
}

std::uint64_t OctreeBinWriter::append(const std::byte* data, std::size_t size) {
  if (fail_after_ > 0 && size_ + size > fail_after_) {
    // Write what fits first, so the interruption leaves a half-written file behind.
    std::fwrite(data, 1, std::size_t(fail_after_ - size_), file_);
    throw std::runtime_error(path_.string() + ": simulated interruption after " +
                             std::to_string(fail_after_) + " bytes");
  }
  if (size > 0 && std::fwrite(data, 1, size, file_) != size) {
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  }
  const std::uint64_t offset = size_;
  size_ += size;
  return offset;
}

std::uint64_t OctreeBinWriter::appendFile(const std::filesystem::path& path) {
  const int in = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
  struct stat info {};
  if (::fstat(in, &info) != 0) {
    ::close(in);
    throw std::runtime_error(path.string() + ": cannot read: " + std::strerror(errno));
  }
  const std::uint64_t offset = size_;
  const std::uint64_t length = std::uint64_t(info.st_size);
  std::uint64_t copied = 0;
  bool fallback = false;
  // What stdio holds goes first; the descriptor's position is then the file's end.
  if (std::fflush(file_) != 0) fallback = true;
  const int out = ::fileno(file_);
  while (!fallback && copied < length) {
    const ssize_t n = ::copy_file_range(in, nullptr, out, nullptr, length - copied, 0);
    if (n <= 0) {
      // Not supported here (another file system, an old kernel): copied by hand from here.
      if (n < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP)) {
        fallback = true;
        break;
      }
      const int error = errno;
      ::close(in);
      throw std::runtime_error(path_.string() + ": cannot append " + path.string() + ": " +
                               (n == 0 ? "it is shorter than its size" : std::strerror(error)));
    }
    copied += std::uint64_t(n);
  }
  if (std::fseek(file_, 0, SEEK_END) != 0) {
    ::close(in);
    throw std::runtime_error(path_.string() + ": cannot seek: " + std::strerror(errno));
  }
  std::vector<std::byte> buffer(fallback ? std::size_t(4) << 20 : 0);
  while (copied < length) {
    const ssize_t n = ::pread(
        in, buffer.data(), std::min<std::uint64_t>(buffer.size(), length - copied), off_t(copied));
    if (n <= 0) {
      const int error = errno;
      ::close(in);
      throw std::runtime_error(path.string() + ": cannot read: " +
                               (n == 0 ? "it is shorter than its size" : std::strerror(error)));
    }
    if (std::fwrite(buffer.data(), 1, std::size_t(n), file_) != std::size_t(n)) {
      ::close(in);
      throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
    }
    copied += std::uint64_t(n);
  }
  ::close(in);
  size_ += length;
  return offset;
}

void OctreeBinWriter::close() {
  if (file_ && std::fclose(file_) != 0) {
    file_ = nullptr;
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  }
  file_ = nullptr;
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

// Builds the chunks several at a time and writes them in chunk order. A chunk is started (in
// chunk order) while the chunks started and not yet written fit in the budget together, or when
// none is in flight; whichever thread finishes the next chunk to write writes it and starts more.
// The output is the same whatever the timing: the order of writing is fixed, not the order of
// finishing.
class ChunkScheduler {
 public:
  ChunkScheduler(const ConvertPlan& plan, std::size_t first, std::size_t last,
                 const ChunkSource& source, const OctreeBuildOptions& options,
                 const Sampler& sampler, OctreeBinWriter& octree,
                 std::vector<PotreeNodeEntry>& entries, Progress* bar)
      : plan_(plan),
        first_(first),
        source_(source),
        options_(options),
        sampler_(sampler),
        octree_(octree),
        entries_(entries),
        bar_(bar),
        bytes_per_point_(chunkBuildBytesPerPoint(plan.layout.recordSize())),
        // The batch's quarter of the budget is free once distribute is done.
        budget_(options.memory_bytes / 4 * 3),
        next_start_(first),
        next_write_(first),
        end_(last),
        built_(last - first),
        roots_(last - first) {}

  std::vector<ChunkRoot> run() {
    {
      std::lock_guard lock(mutex_);
      startMore();
    }
    group_.wait();
    return std::move(roots_);
  }

 private:
  // Called with mutex_ held.
  void startMore() {
    while (!failed_ && next_start_ < end_) {
      const std::uint64_t cost = plan_.chunks[next_start_].points * bytes_per_point_;
      if (in_flight_bytes_ > 0 && in_flight_bytes_ + cost > budget_) break;
      in_flight_bytes_ += cost;
      const std::size_t index = next_start_++;
      group_.run([this, index] { buildAndWrite(index); });
    }
  }

  void buildAndWrite(std::size_t index) {
    try {
      BuiltChunk chunk = buildOneChunk(plan_, index, source_, options_, sampler_);
      std::unique_lock lock(mutex_);
      if (failed_) return;
      built_[index - first_] = std::move(chunk);
      if (writing_) return;  // the thread writing now will get to it
      writing_ = true;
      while (next_write_ < end_ && built_[next_write_ - first_]) {
        BuiltChunk ready = std::move(*built_[next_write_ - first_]);
        built_[next_write_ - first_].reset();
        const std::size_t written = next_write_;
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

  // Appends the chunk's nodes but its root to octree.bin (only the writing thread calls it).
  ChunkRoot writeChunk(std::size_t index, const BuiltChunk& chunk) {
    const std::size_t record = plan_.layout.recordSize();
    const BuiltNode& root = chunk.nodes.front();
    const std::size_t root_bytes = std::size_t(root.count) * record;
    const std::uint64_t base =
        octree_.append(chunk.records.data() + root_bytes, chunk.records.size() - root_bytes);
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
  std::size_t next_start_;
  std::size_t next_write_;
  const std::size_t end_;
  std::vector<std::optional<BuiltChunk>> built_;  // finished, not yet written (from first_)
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
  return buildChunkRange(plan, 0, plan.chunks.size(), mapped, options, sampler, octree, entries,
                         bar.get());
}

std::vector<ChunkRoot> buildChunkRange(const ConvertPlan& plan, std::size_t first, std::size_t last,
                                       const ChunkSource& source, const OctreeBuildOptions& options,
                                       const Sampler& sampler, OctreeBinWriter& octree,
                                       std::vector<PotreeNodeEntry>& entries, Progress* bar) {
  assert(first <= last && last <= plan.chunks.size() && "buildChunkRange: chunks of the plan");
  ChunkScheduler scheduler(plan, first, last, source, options, sampler, octree, entries, bar);
  return scheduler.run();
}

}  // namespace parallax
