// Stage 3 of the conversion (convert_stages.h): every point, encoded once as its octree.bin
// record, is appended to the spill file of its chunk.
//
// A batch is encoded in parallel, then its records are grouped by chunk with a counting sort and
// each group is appended with one write, so the spill files are written in large sequential
// pieces however the points are ordered in the input. The writes of one batch overlap the
// reading of the next (two grouped buffers; the budget counts both).
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "lod/convert_stages.h"

namespace parallax {
namespace {

// Spill files kept open at once; beyond that each append opens and closes its file.
constexpr std::size_t kMaxOpenFiles = 200;

[[noreturn]] void failIo(const std::filesystem::path& path, const char* what) {
  throw std::runtime_error(path.string() + ": " + what + ": " + std::strerror(errno));
}

class SpillFiles {
 public:
  SpillFiles(const std::filesystem::path& dir, std::size_t count)
      : dir_(dir), files_(count, nullptr), keep_open_(count <= kMaxOpenFiles) {}
  ~SpillFiles() {
    for (std::FILE* file : files_)
      if (file) std::fclose(file);
  }
  void append(std::size_t chunk, const std::byte* data, std::size_t size) {
    const auto path = chunkFilePath(dir_, chunk);
    std::FILE* file = files_[chunk];
    if (!file) file = std::fopen(path.c_str(), "ab");
    if (!file) failIo(path, "cannot open the spill file");
    if (std::fwrite(data, 1, size, file) != size) failIo(path, "cannot write the spill file");
    if (keep_open_) {
      files_[chunk] = file;
    } else if (std::fclose(file) != 0) {
      failIo(path, "cannot write the spill file");
    }
  }
  void closeAll() {
    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (files_[i] && std::fclose(files_[i]) != 0) {
        files_[i] = nullptr;
        failIo(chunkFilePath(dir_, i), "cannot write the spill file");
      }
      files_[i] = nullptr;
    }
  }

 private:
  std::filesystem::path dir_;
  std::vector<std::FILE*> files_;
  bool keep_open_;
};

// One batch's records grouped by chunk: chunk c's are records[start[c], start[c + 1]).
struct GroupedBatch {
  ByteBuffer records;
  std::vector<std::uint64_t> start;
};

}  // namespace

std::filesystem::path chunkFilePath(const std::filesystem::path& chunk_dir, std::size_t index) {
  return chunk_dir / ("chunk_" + std::to_string(index) + ".bin");
}

namespace {

// Appends the records of streams to the spill files of their chunks, widening plan.stats.
class Distributor {
 public:
  Distributor(ConvertPlan& plan, const std::filesystem::path& chunk_dir)
      : plan_(plan),
        spill_(chunk_dir, plan.chunks.size()),
        record_(plan.layout.recordSize()),
        delivered_(plan.chunks.size(), 0) {}

  // Every point of `stream` (read from `input`, named in errors).
  void add(PointStream& stream, const std::filesystem::path& input, Progress* bar) {
    // Two grouped batches: one is written to the spill files (a task) while the next is read,
    // encoded and grouped into the other, so the writes (the kernel's copies) overlap the reading.
    GroupedBatch grouped[2];
    std::size_t slot = 0;
    tbb::task_group writer;
    try {
      PointCloud batch;
      while (stream.next(batch, plan_.batch_points)) {
        throwIfBuildCancelled(plan_.cancel);
        GroupedBatch& out = grouped[slot];
        group(batch, input, out);
        writer.wait();  // the other slot's batch is written (rethrows its error)
        writer.run([this, &out] { write(out); });
        slot ^= 1;
        if (bar) bar->advance(batch.count);
      }
      writer.wait();
    } catch (...) {
      try {
        writer.wait();  // never leave the task running on buffers about to go
      } catch (...) {
      }
      throw;
    }
  }

  // Closes the spill files; the points each chunk received.
  const std::vector<std::uint64_t>& finish() {
    spill_.closeAll();
    return delivered_;
  }

 private:
  // Encodes a batch and sorts its records by chunk (a counting sort) into `out`.
  void group(const PointCloud& batch, const std::filesystem::path& input, GroupedBatch& out) {
    const std::uint64_t n = batch.count;
    const std::size_t record = record_;
    if (records_.size() < n * record) records_ = ByteBuffer(n * record);
    chunk_of_.resize(n);
    tbb::combinable<AttributeStats> stats([&] { return plan_.layout.emptyStats(); });
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, n, 1 << 14), [&](const auto& range) {
      std::byte* encoded = records_.data() + range.begin() * record;
      plan_.layout.encode(batch, range.begin(), range.size(), plan_.quantization, encoded,
                          stats.local());
      for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
        Int3 p;
        std::memcpy(&p, records_.data() + i * record, sizeof p);
        chunk_of_[i] = plan_.cell_chunk[plan_.cellOf(p)];
      }
    });
    stats.combine_each([&](const AttributeStats& s) { plan_.stats.merge(s); });

    if (out.records.size() < n * record) out.records = ByteBuffer(n * record);
    out.start.assign(plan_.chunks.size() + 1, 0);
    for (std::uint64_t i = 0; i < n; ++i) {
      if (chunk_of_[i] < 0) {
        // The count pass saw this cell empty: the input changed between the passes.
        throw InputError({.file = input.string(),
                          .expected = "the same points in every pass of the conversion",
                          .found = "a point in a region that was empty when counting",
                          .hint = "do not modify the input while it is being converted"});
      }
      ++out.start[std::size_t(chunk_of_[i]) + 1];
    }
    for (std::size_t c = 0; c < plan_.chunks.size(); ++c) out.start[c + 1] += out.start[c];
    std::vector<std::uint64_t> at(out.start.begin(), out.start.end() - 1);
    for (std::uint64_t i = 0; i < n; ++i) {
      std::memcpy(out.records.data() + at[std::size_t(chunk_of_[i])]++ * record,
                  records_.data() + i * record, record);
    }
  }

  void write(const GroupedBatch& batch) {
    for (std::size_t c = 0; c < plan_.chunks.size(); ++c) {
      const std::uint64_t count = batch.start[c + 1] - batch.start[c];
      if (count == 0) continue;
      spill_.append(c, batch.records.data() + batch.start[c] * record_, count * record_);
      delivered_[c] += count;
    }
  }

  ConvertPlan& plan_;
  SpillFiles spill_;
  const std::size_t record_;
  std::vector<std::uint64_t> delivered_;
  ByteBuffer records_;
  std::vector<std::int32_t> chunk_of_;
};

}  // namespace

void distributePoints(ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                      const std::filesystem::path& chunk_dir, const ProgressFactory& progress) {
  std::filesystem::create_directories(chunk_dir);
  std::unique_ptr<Progress> bar = progress ? progress("distributing", plan.points) : nullptr;
  Distributor distributor(plan, chunk_dir);
  for (std::size_t input = 0; input < inputs.size(); ++input) {
    PointStream stream = openPassStream(plan, inputs, input, true);
    distributor.add(stream, inputs[input].path, bar.get());
  }
  const std::vector<std::uint64_t>& delivered = distributor.finish();
  for (std::size_t c = 0; c < plan.chunks.size(); ++c) {
    if (delivered[c] != plan.chunks[c].points) {
      throw InputError({.file = inputs.front().path.string(),
                        .expected = std::to_string(plan.chunks[c].points) + " points in chunk " +
                                    plan.chunks[c].name + " (counted)",
                        .found = std::to_string(delivered[c]),
                        .hint = "do not modify the input while it is being converted"});
    }
  }
}

std::vector<std::uint64_t> distributeStream(ConvertPlan& plan, PointStream& stream,
                                            const std::filesystem::path& input,
                                            const std::filesystem::path& shard_dir, Progress* bar) {
  std::filesystem::create_directories(shard_dir);
  Distributor distributor(plan, shard_dir);
  distributor.add(stream, input, bar);
  return distributor.finish();
}

}  // namespace parallax
