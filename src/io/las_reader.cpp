#include "io/las_reader.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cstring>
#include <mutex>
#include <vector>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "core/error.h"
#include "io/las_record_decoder.h"
#include "io/laz_reader.h"
#include "io/mapped_file.h"
#include "io/read_ahead.h"

namespace parallax {
namespace {

// Records read at a time into a thread's buffer: about 1-2 MB, small enough to stay in L2/L3
// while decoded, large enough that the read() calls cost nothing.
constexpr std::uint64_t kBlockRecords = 1 << 15;
// A local file's blocks are smaller: read() costs little there, and a buffer of 128-256 KiB
// leaves L2 room for the lines of the twenty-odd columns being written (20 M records of 38 bytes,
// load 14 on 2 cores: 0-10 % less CPU a read than with 1.2 MB blocks, within the noise).
constexpr std::uint64_t kLocalBlockRecords = 1 << 12;
constexpr std::uint64_t kColorSamples = 4096;

// Blocks of a remote file hinted ahead of the decode (io/read_ahead.h): 8 blocks of 1-2 MB.
constexpr std::size_t kReadAheadBlocks = 8;

// Calls fn(i) for i in [0, count) on every core, handing the indices out in increasing order, so
// that reads of a remote file follow its read-ahead (a parallel_for over a range splits it in
// halves, and the second half's reads would wait on the network unhinted).
template <class F>
void forEachInOrder(std::size_t count, bool parallel, F fn) {
  const std::size_t workers =
      parallel ? std::min<std::size_t>(
                     count, std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())))
               : 1;
  std::atomic<std::size_t> next{0};
  auto work = [&](std::size_t) {
    for (std::size_t i = next++; i < count; i = next++) fn(i);
  };
  if (workers <= 1) {
    work(0);
  } else {
    tbb::parallel_for(std::size_t(0), workers, work);
  }
}

// The 8-bit rule (las_reader.h) from a strided sample: a value of 256 or more settles it (16-bit).
// Otherwise the decode guesses 8-bit and checks every colour on the way. Not for a remote file,
// where 4096 scattered reads would be 4096 requests: it guesses 8-bit (the common case) at once.
bool sampleHas16BitColors(const ByteSource& in, const LasHeader& header,
                          const LasDecodePlan& plan) {
  if (!plan.color_offset || header.point_count == 0 || !in.local()) return false;
  const std::uint64_t stride = std::max<std::uint64_t>(1, header.point_count / kColorSamples);
  std::byte rgb[6];
  for (std::uint64_t i = 0; i < header.point_count; i += stride) {
    in.read(header.point_data_offset + i * plan.record_length + *plan.color_offset, rgb,
            {.element = "colour sample"});
    std::uint16_t c[3];
    std::memcpy(c, rgb, 6);
    if ((c[0] | c[1] | c[2]) > 255) return true;
  }
  return false;
}

// Calls fn(records, n, index) for the records [first, first + count) of the file, a block at a
// time through per-thread buffers (`index` counts from `first`). A remote file is read in blocks
// on a fixed grid of kBlockRecords from the first record, in order, with the next blocks hinted
// ahead: every pass over the same records reads the same ranges, which the range cache then
// serves (a stream's colour pass, then its chunks).
template <class F>
void forEachBlock(const ByteSource& in, const LasHeader& header, std::uint64_t first,
                  std::uint64_t count, bool parallel, F fn) {
  const std::size_t length = header.record_length;
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  // `read` is called as soon as the block's bytes are in, before it is decoded (the read-ahead
  // must not hint again a range whose read has returned: the source would fetch it anew).
  auto readBlock = [&](std::uint64_t b, std::size_t n, auto read) {
    std::vector<std::byte>& buffer = buffers.local();
    buffer.resize(std::max(buffer.size(), n * length));
    in.read(header.point_data_offset + b * length, std::span(buffer.data(), n * length),
            {.element = "point records"});
    read();
    fn(buffer.data(), n, std::size_t(b - first));
  };
  if (!in.local()) {
    if (count == 0) return;
    const std::uint64_t end = first + count;
    const std::uint64_t grid_first = first / kBlockRecords;
    const std::size_t blocks = std::size_t((end - 1) / kBlockRecords - grid_first + 1);
    auto blockOf = [&](std::size_t k) {
      const std::uint64_t b = std::max(first, (grid_first + k) * kBlockRecords);
      return std::pair(b, std::min(end, (grid_first + k + 1) * kBlockRecords) - b);
    };
    std::vector<ByteRange> plan(blocks);
    for (std::size_t k = 0; k < blocks; ++k) {
      const auto [b, n] = blockOf(k);
      plan[k] = {header.point_data_offset + b * length, n * length};
    }
    ReadAhead ahead(in, std::move(plan), kReadAheadBlocks);
    forEachInOrder(blocks, parallel, [&](std::size_t k) {
      const auto [b, n] = blockOf(k);
      readBlock(b, std::size_t(n), [&] { ahead.finished(k); });
    });
    return;
  }
  auto body = [&](const tbb::blocked_range<std::uint64_t>& range) {
    for (std::uint64_t b = range.begin(); b < range.end(); b += kLocalBlockRecords) {
      readBlock(b, std::size_t(std::min(kLocalBlockRecords, range.end() - b)), [] {});
    }
  };
  const tbb::blocked_range<std::uint64_t> all(first, first + count, kBlockRecords);
  if (parallel) {
    tbb::parallel_for(all, body);
  } else {
    body(all);
  }
}

// Decodes records [first, first + count) into `cloud` (allocated for `count` points) and
// returns the bounds; a second pass over the colours when the 8-bit guess was wrong.
Bounds3 decodeRecords(const ByteSource& in, const LasHeader& header, LasDecodePlan& plan,
                      PointCloud& cloud, std::uint64_t first, std::uint64_t count, bool parallel,
                      Progress* progress) {
  LasDecodeStats stats;
  std::mutex stats_mutex;
  forEachBlock(in, header, first, count, parallel,
               [&](const std::byte* records, std::size_t n, std::size_t at) {
                 LasDecodeStats local;
                 decodeLasRecords(records, n, plan, cloud, at, local);
                 if (progress) progress->advance(n);
                 std::lock_guard lock(stats_mutex);
                 stats.merge(local);
               });
  if (plan.colors_8bit && stats.color_above_255) {
    plan.colors_8bit = false;
    cloud.source.color = ScalarType::UInt16;
    forEachBlock(in, header, first, count, parallel,
                 [&](const std::byte* records, std::size_t n, std::size_t at) {
                   decodeLasColors(records, n, plan, cloud, at);
                 });
  }
  return stats.world(cloud.quantization);
}

PointCloud readAll(const ByteSource& in, const LasHeader& header, const LasReadOptions& options) {
  LasDecodePlan plan = makeLasDecodePlan(header);
  plan.colors_8bit = !sampleHas16BitColors(in, header, plan);
  const std::size_t count = header.point_count;
  PointCloud cloud = allocateLasCloud(header, plan, count);
  if (in.local()) {
    // The kernel reads the records ahead (a remote file's blocks are hinted by forEachBlock).
    const ByteRange records{header.point_data_offset, std::uint64_t(count) * plan.record_length};
    in.prefetch(std::span(&records, 1));
  }
  cloud.bounds =
      decodeRecords(in, header, plan, cloud, 0, count, options.parallel, options.progress);
  return cloud;
}

}  // namespace

PointCloud readLas(const std::filesystem::path& path, const LasReadOptions& options) {
  if (!isUrl(path.string()) && !std::filesystem::is_regular_file(path)) {
    // A pipe or a special file: read whole into memory (MappedFile's fallback) first.
    const MappedFile file(path);
    return readLasFromMemory(file.bytes(), path.string(), options);
  }
  // A file or a URL: the header, then the records by range.
  const std::unique_ptr<ByteSource> in = openLasSource(path);
  const LasHeader header = readLasHeader(*in);
  if (header.laszip) {
    return readLaz(path, {.progress = options.progress, .parallel = options.parallel});
  }
  return readAll(*in, header, options);
}

PointCloud readLasFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const LasReadOptions& options) {
  const LasHeader header = parseLasHeader(bytes, name);
  if (header.laszip) {
    return readLazFromMemory(bytes, name,
                             {.progress = options.progress, .parallel = options.parallel});
  }
  return readAll(*viewMemorySource(bytes, name), header, options);
}

PointCloud readLasPreview(const std::filesystem::path& path, std::uint64_t max_points) {
  const std::unique_ptr<ByteSource> source = openLasSource(path);
  const ByteSource& in = *source;
  const LasHeader header = readLasHeader(in);
  if (header.laszip) return readLazPreview(path, max_points);
  if (header.point_count <= max_points) return readAll(in, header, {});
  // Runs of consecutive records: one read each, and neighbours of a scan give the adaptive
  // point size a local spacing. A remote file's read is a request: its runs are longer, so
  // that a preview is at most about 256 requests (hinted ahead, several in flight).
  const std::uint64_t kRun =
      in.local() ? 64 : std::max<std::uint64_t>(64, std::bit_ceil(max_points / 256));
  const std::uint64_t runs = std::max<std::uint64_t>(1, max_points / kRun);
  const std::uint64_t step = header.point_count / runs;
  LasDecodePlan plan = makeLasDecodePlan(header);
  const std::size_t length = plan.record_length;
  PointCloud cloud = allocateLasCloud(header, plan, std::size_t(runs * kRun));
  LasDecodeStats stats;
  std::mutex stats_mutex;
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  auto pass = [&](bool colors_only) {
    std::vector<ByteRange> reads(static_cast<std::size_t>(runs));
    for (std::uint64_t r = 0; r < runs; ++r) {
      reads[std::size_t(r)] = {header.point_data_offset + r * step * length, kRun * length};
    }
    ReadAhead ahead(in, reads, kReadAheadBlocks);
    forEachInOrder(std::size_t(runs), true, [&](std::size_t r) {
      std::vector<std::byte>& buffer = buffers.local();
      buffer.resize(kRun * length);
      in.read(reads[r].offset, buffer, {.element = "point records"});
      ahead.finished(r);
      if (colors_only) {
        decodeLasColors(buffer.data(), kRun, plan, cloud, std::size_t(r * kRun));
        return;
      }
      LasDecodeStats local;
      decodeLasRecords(buffer.data(), kRun, plan, cloud, std::size_t(r * kRun), local);
      const std::lock_guard lock(stats_mutex);
      stats.merge(local);
    });
  };
  pass(false);
  if (stats.color_above_255) {
    plan.colors_8bit = false;
    cloud.source.color = ScalarType::UInt16;
    pass(true);
  }
  cloud.bounds = stats.world(cloud.quantization);
  return cloud;
}

struct LasChunkReader::State {
  std::unique_ptr<ByteSource> in;
  LasHeader header;
  LasDecodePlan plan;
  std::uint64_t next = 0;
  CoordinateSystem crs;
};

LasChunkReader::LasChunkReader(const std::filesystem::path& path) {
  std::unique_ptr<ByteSource> in = openLasSource(path);
  LasHeader header = readLasHeader(*in);
  if (header.laszip) {
    throw InputError({.file = path.string(),
                      .byte_offset = 104,
                      .element = "header",
                      .property = "point data format",
                      .expected = "an uncompressed LAS file (LasChunkReader)",
                      .found = "a LAZ file",
                      .hint = "read it with LazChunkReader"});
  }
  LasDecodePlan plan = makeLasDecodePlan(header);
  // A stream cannot go back to rewrite colours: every colour is checked before the first chunk
  // (one pass through per-thread buffers) unless the sample settles it.
  bool big = sampleHas16BitColors(*in, header, plan);
  if (!big && plan.color_offset) {
    std::atomic<bool> found{false};
    forEachBlock(
        *in, header, 0, header.point_count, true,
        [&](const std::byte* records, std::size_t n, std::size_t) {
          if (!found.load(std::memory_order_relaxed) && lasColorsAbove255(records, n, plan)) {
            found = true;
          }
        });
    big = found;
  }
  plan.colors_8bit = !big;
  CoordinateSystem crs = coordinateSystemOf(header);
  state_ = std::make_unique<State>(
      State{std::move(in), std::move(header), std::move(plan), 0, std::move(crs)});
}
LasChunkReader::~LasChunkReader() = default;
LasChunkReader::LasChunkReader(LasChunkReader&&) noexcept = default;

const LasHeader& LasChunkReader::header() const {
  return state_->header;
}
const CoordinateSystem& LasChunkReader::crs() const {
  return state_->crs;
}
std::uint64_t LasChunkReader::pointCount() const {
  return state_->header.point_count;
}
const Quantization& LasChunkReader::quantization() const {
  return state_->header.quantization;
}

bool LasChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  assert(max_points > 0 && "LasChunkReader::next needs a positive chunk size");
  State& s = *state_;
  std::size_t n = std::size_t(std::min<std::uint64_t>(max_points, s.header.point_count - s.next));
  chunk = allocateLasCloud(s.header, s.plan, n);
  if (n == 0) return false;
  chunk.bounds = decodeRecords(*s.in, s.header, s.plan, chunk, s.next, n, true, nullptr);
  s.next += n;
  return true;
}

void LasChunkReader::skip(std::uint64_t count) {
  State& s = *state_;
  s.next += std::min(count, s.header.point_count - s.next);
}

}  // namespace parallax
