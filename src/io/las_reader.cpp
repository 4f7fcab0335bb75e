#include "io/las_reader.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
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

namespace parallax {
namespace {

// Records read at a time into a thread's buffer: about 1-2 MB, small enough to stay in L2/L3
// while decoded, large enough that the read() calls cost nothing.
constexpr std::uint64_t kBlockRecords = 1 << 15;
constexpr std::uint64_t kColorSamples = 4096;

// The 8-bit rule (las_reader.h) from a strided sample: a value of 256 or more settles it (16-bit).
// Otherwise the decode guesses 8-bit and checks every colour on the way.
bool sampleHas16BitColors(const ByteSource& in, const LasHeader& header,
                          const LasDecodePlan& plan) {
  if (!plan.color_offset || header.point_count == 0) return false;
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
// time through per-thread buffers (`index` counts from `first`).
template <class F>
void forEachBlock(const ByteSource& in, const LasHeader& header, std::uint64_t first,
                  std::uint64_t count, bool parallel, F fn) {
  const std::size_t length = header.record_length;
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  auto body = [&](const tbb::blocked_range<std::uint64_t>& range) {
    std::vector<std::byte>& buffer = buffers.local();
    for (std::uint64_t b = range.begin(); b < range.end(); b += kBlockRecords) {
      const std::size_t n = std::size_t(std::min(kBlockRecords, range.end() - b));
      buffer.resize(std::max(buffer.size(), n * length));
      in.read(header.point_data_offset + b * length, std::span(buffer.data(), n * length),
              {.element = "point records"});
      fn(buffer.data(), n, std::size_t(b - first));
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
  const ByteRange records{header.point_data_offset, std::uint64_t(count) * plan.record_length};
  in.prefetch(std::span(&records, 1));
  cloud.bounds =
      decodeRecords(in, header, plan, cloud, 0, count, options.parallel, options.progress);
  return cloud;
}

}  // namespace

PointCloud readLas(const std::filesystem::path& path, const LasReadOptions& options) {
  if (!std::filesystem::is_regular_file(path)) {
    // A pipe or a special file: read whole into memory (MappedFile's fallback) first.
    const MappedFile file(path);
    return readLasFromMemory(file.bytes(), path.string(), options);
  }
  const LasHeader header = readLasHeader(path);
  if (header.laszip) {
    return readLaz(path, {.progress = options.progress, .parallel = options.parallel});
  }
  return readAll(*openByteSource(path.string()), header, options);
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
  const LasHeader header = readLasHeader(path);
  if (header.laszip) return readLazPreview(path, max_points);
  if (header.point_count <= max_points) return readLas(path);
  // Runs of consecutive records: one read each, and neighbours of a scan give the adaptive
  // point size a local spacing.
  constexpr std::uint64_t kRun = 64;
  const std::unique_ptr<ByteSource> source = openByteSource(path.string());
  const ByteSource& in = *source;
  const std::uint64_t runs = std::max<std::uint64_t>(1, max_points / kRun);
  const std::uint64_t step = header.point_count / runs;
  LasDecodePlan plan = makeLasDecodePlan(header);
  const std::size_t length = plan.record_length;
  PointCloud cloud = allocateLasCloud(header, plan, std::size_t(runs * kRun));
  LasDecodeStats stats;
  std::mutex stats_mutex;
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  auto pass = [&](bool colors_only) {
    tbb::parallel_for(std::uint64_t(0), runs, [&](std::uint64_t r) {
      std::vector<std::byte>& buffer = buffers.local();
      buffer.resize(kRun * length);
      in.read(header.point_data_offset + r * step * length, buffer, {.element = "point records"});
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
  LasHeader header = readLasHeader(path);
  if (header.laszip) {
    throw InputError({.file = path.string(),
                      .byte_offset = 104,
                      .element = "header",
                      .property = "point data format",
                      .expected = "an uncompressed LAS file (LasChunkReader)",
                      .found = "a LAZ file",
                      .hint = "read it with LazChunkReader"});
  }
  std::unique_ptr<ByteSource> in = openByteSource(path.string());
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
