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

void distributePoints(ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                      const std::filesystem::path& chunk_dir, const ProgressFactory& progress) {
  std::filesystem::create_directories(chunk_dir);
  SpillFiles spill(chunk_dir, plan.chunks.size());
  const std::size_t record = plan.layout.recordSize();
  std::vector<std::uint64_t> delivered(plan.chunks.size(), 0);
  std::unique_ptr<Progress> bar = progress ? progress("distributing", plan.points) : nullptr;
  ByteBuffer records;
  std::vector<std::int32_t> chunk_of;
  // Two grouped batches: one is written to the spill files (a task) while the next is read,
  // encoded and grouped into the other, so the writes (the kernel's copies) overlap the reading.
  GroupedBatch grouped[2];
  std::size_t slot = 0;
  tbb::task_group writer;
  auto writeBatch = [&](const GroupedBatch& batch) {
    for (std::size_t c = 0; c < plan.chunks.size(); ++c) {
      const std::uint64_t count = batch.start[c + 1] - batch.start[c];
      if (count == 0) continue;
      spill.append(c, batch.records.data() + batch.start[c] * record, count * record);
      delivered[c] += count;
    }
  };
  try {
    for (std::size_t input = 0; input < inputs.size(); ++input) {
      PointStream stream(inputs[input].path, inputs[input].text_columns,
                         &plan.input_quantizations[input], &inputs[input].filter);
      PointCloud batch;
      while (stream.next(batch, plan.batch_points)) {
        const std::uint64_t n = batch.count;
        if (records.size() < n * record) records = ByteBuffer(n * record);
        chunk_of.resize(n);
        tbb::combinable<AttributeStats> stats([&] { return plan.layout.emptyStats(); });
        tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, n, 1 << 14), [&](const auto& range) {
          std::byte* out = records.data() + range.begin() * record;
          plan.layout.encode(batch, range.begin(), range.size(), plan.quantization, out,
                             stats.local());
          for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
            Int3 p;
            std::memcpy(&p, records.data() + i * record, sizeof p);
            chunk_of[i] = plan.cell_chunk[plan.cellOf(p)];
          }
        });
        stats.combine_each([&](const AttributeStats& s) { plan.stats.merge(s); });

        // Counting sort of the records by chunk, into the slot not being written.
        GroupedBatch& out = grouped[slot];
        if (out.records.size() < n * record) out.records = ByteBuffer(n * record);
        out.start.assign(plan.chunks.size() + 1, 0);
        for (std::uint64_t i = 0; i < n; ++i) {
          if (chunk_of[i] < 0) {
            // The count pass saw this cell empty: the input changed between the passes.
            throw InputError({.file = inputs[input].path.string(),
                              .expected = "the same points in every pass of the conversion",
                              .found = "a point in a region that was empty when counting",
                              .hint = "do not modify the input while it is being converted"});
          }
          ++out.start[std::size_t(chunk_of[i]) + 1];
        }
        for (std::size_t c = 0; c < plan.chunks.size(); ++c) out.start[c + 1] += out.start[c];
        std::vector<std::uint64_t> at(out.start.begin(), out.start.end() - 1);
        for (std::uint64_t i = 0; i < n; ++i) {
          std::memcpy(out.records.data() + at[std::size_t(chunk_of[i])]++ * record,
                      records.data() + i * record, record);
        }
        writer.wait();  // the other slot's batch is written (rethrows its error)
        writer.run([&writeBatch, &out] { writeBatch(out); });
        slot ^= 1;
        if (bar) bar->advance(n);
      }
    }
    writer.wait();
  } catch (...) {
    try {
      writer.wait();  // never leave the task running on buffers about to go
    } catch (...) {
    }
    throw;
  }
  spill.closeAll();
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

}  // namespace parallax
