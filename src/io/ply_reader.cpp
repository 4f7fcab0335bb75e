// Reading PLY files: header, plan, quantization, parallel decode.
//
// The flow of readPly:
//   1. parse the header and map the point element's properties onto columns;
//   2. cut the body into ranges (checking every count against the file size first);
//   3. choose the quantization from a strided sample of positions with a 16x margin;
//   4. allocate the columns once and decode all ranges in parallel straight into them;
//   5. if a point fell outside the sampled quantization (an outlier the sample missed), decode
//      again with the exact bounds now known. Rare, and the price of never holding a second copy
//      of the cloud (every public parser keeps the raw bytes and the decoded values at once).
#include "io/ply_reader.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include "core/byte_source.h"
#include "core/error.h"
#include "io/mapped_file.h"
#include "io/ply_decoder.h"

namespace parallax {
namespace ply {
namespace {
Bounds3 sampleRecords(const DecodeContext& context, const std::vector<RecordRange>& ranges,
                      std::size_t max_samples);
}  // namespace

std::vector<RecordRange> planRanges(const DecodeContext& context, std::size_t target_bytes,
                                    bool parallel) {
  if (context.header.format == PlyFormat::Ascii) {
    return planAsciiRanges(context, target_bytes, parallel);
  }
  return planBinaryRanges(context, target_bytes);
}

RangeStats decodeRange(const DecodeContext& context, const RecordRange& range, std::uint64_t count,
                       PointCloud& cloud, std::uint64_t first_index) {
  if (context.header.format == PlyFormat::Ascii) {
    return decodeAsciiRange(context, range, count, cloud, first_index);
  }
  return decodeBinaryRange(context, range, count, cloud, first_index);
}

Bounds3 sampleBounds(const DecodeContext& context, const std::vector<RecordRange>& ranges,
                     std::size_t max_samples) {
  return sampleRecords(context, ranges, max_samples);
}

namespace {

Bounds3 sampleRecords(const DecodeContext& context, const std::vector<RecordRange>& ranges,
                      std::size_t max_samples) {
  Bounds3 bounds;
  if (ranges.empty()) return bounds;
  PointCloud scratch = allocatePointCloud(context.layout, 1, Quantization{});
  // A fault maps neighbouring pages too (the kernel's fault-around, 64 KiB, or a whole large
  // page-cache folio, up to 2 MiB): without releasing them, a few thousand samples would keep
  // much of the file resident. They are released in batches, as each release is a system call
  // and a TLB flush on every core.
  constexpr std::size_t kFaultAround = 2 << 20;
  constexpr int kBatch = 32;
  std::size_t batch_lo = SIZE_MAX, batch_hi = 0;
  int batched = 0;
  auto release = [&] {
    if (batched == 0) return;
    std::size_t from = batch_lo > kFaultAround ? batch_lo - kFaultAround : 0;
    context.releaseRead(from & ~(kFaultAround - 1), batch_hi + 2 * kFaultAround);
    batch_lo = SIZE_MAX, batch_hi = 0, batched = 0;
  };
  auto sample = [&](const RecordRange& one) {
    try {
      bounds.extend(decodeRange(context, one, 1, scratch, 0).raw_bounds);
    } catch (const InputError&) {
      // Reported with its line or offset by the full decode.
    }
    batch_lo = std::min(batch_lo, one.begin), batch_hi = std::max(batch_hi, one.begin);
    if (++batched == kBatch) release();
  };
  struct ReleaseAtEnd {
    decltype(release)& fn;
    ~ReleaseAtEnd() { fn(); }
  } release_at_end{release};
  const std::uint64_t total = ranges.back().first_record + ranges.back().count;
  if (context.header.format != PlyFormat::Ascii && context.layout.fixed_size) {
    std::uint64_t samples = std::min<std::uint64_t>(max_samples, total);
    for (std::uint64_t k = 0; k < samples; ++k) {
      std::uint64_t record = k * total / samples;
      std::size_t begin = ranges.front().begin + record * context.layout.record_size;
      sample({record, 1, begin, 0});
    }
    sample({total - 1, 1, ranges.front().begin + (total - 1) * context.layout.record_size, 0});
    return bounds;
  }
  for (const auto& range : ranges) sample({range.first_record, 1, range.begin, 0});
  if (context.header.format != PlyFormat::Ascii) return bounds;
  // Ascii: lines at evenly spaced bytes; a line that is not a point record (past the element)
  // fails to parse and is skipped.
  const char* text = reinterpret_cast<const char*>(context.bytes.data());
  std::size_t begin = ranges.front().begin, end = context.bytes.size();
  std::size_t last_line_start = begin;
  for (std::size_t k = 1; k < max_samples && end > begin; ++k) {
    std::size_t at = begin + std::size_t(double(end - begin) * double(k) / double(max_samples));
    if (at < last_line_start) continue;  // still inside the line sampled last
    const void* newline = std::memchr(text + at, '\n', end - at);
    if (newline == nullptr) break;
    std::size_t line_start = std::size_t(static_cast<const char*>(newline) - text) + 1;
    if (line_start < end) sample({0, 1, line_start, 0});
    last_line_start = line_start + 1;
  }
  return bounds;
}

}  // namespace
}  // namespace ply

namespace {

using ply::DecodeContext;
using ply::RecordRange;

// About 512 KiB of input a range: small enough to stay in L2 while its properties are decoded
// one after another, large enough that scheduling costs nothing.
constexpr std::size_t kRangeBytes = 512 << 10;
// Fixed-size binary records read by range (pread) come in blocks of this size into a buffer of
// the thread: small enough that the buffer and the columns' lines being written share L2 with the
// other hyper-thread (20 M points of 27 bytes, same run: 0.52 s of CPU a read with blocks of
// 512 KiB, 0.41-0.46 s with 64 or 128 KiB).
constexpr std::size_t kReadBlockBytes = 128 << 10;

int requirePointElement(const PlyHeader& header, const std::string& file) {
  int index = header.pointElement();
  if (index >= 0) return index;
  std::string found;
  for (const auto& element : header.elements) found += (found.empty() ? "" : ", ") + element.name;
  throw InputError({.file = file,
                    .expected = "an element named vertex (or vertices, point, points)",
                    .found = found.empty() ? "no elements" : "elements " + found});
}

bool fitsQuantization(const Quantization& q, const Bounds3& bounds) {
  if (bounds.empty()) return true;
  for (int axis = 0; axis < 3; ++axis) {
    if (!q.fits(axis, bounds.min[axis]) || !q.fits(axis, bounds.max[axis])) return false;
  }
  return true;
}

// World bounds of the quantized points: quantization is monotonic, so the quantized raw extremes
// are the extremes of the quantized points.
Bounds3 quantizedBounds(const Quantization& q, const Bounds3& raw) {
  Bounds3 bounds;
  if (raw.empty()) return bounds;
  for (int axis = 0; axis < 3; ++axis) {
    bounds.min[axis] = q.toWorld(axis, q.toQuantized(axis, raw.min[axis]));
    bounds.max[axis] = q.toWorld(axis, q.toQuantized(axis, raw.max[axis]));
  }
  return bounds;
}

struct DecodeResult {
  Bounds3 raw_bounds;
  std::size_t end = 0;
};

// Whether the decode reads the records through pread (`records`) rather than the mapping: only
// fixed-size binary records, whose ranges are plain byte spans.
bool readsRecordsByRange(const DecodeContext& context) {
  return context.header.format != PlyFormat::Ascii && context.layout.fixed_size;
}

// Decodes the first `count` records of `range` (fixed-size binary) into `cloud` from point
// `first_index`, reading them from `records` in blocks of whole records into `buffer` (a buffer
// of the calling thread, grown to a block): the kernel's copy from the page cache runs at memcpy
// speed over its own mapping of memory, and the decode's loads then hit L2, where through the
// mapping every 4 KiB page was a fault (or at least a TLB miss) and the first load of each cache
// line of a 540 MB file went to DRAM (most of the decode's time). The last block of a range
// holds what is left (a range need not be a multiple of the block).
ply::RangeStats decodeByBlocks(const DecodeContext& context, const ByteSource& records,
                               const RecordRange& range, std::uint64_t count, PointCloud& cloud,
                               std::uint64_t first_index, std::vector<std::byte>& buffer) {
  const std::size_t size = context.layout.record_size;
  const std::uint64_t per_block = std::max<std::size_t>(1, kReadBlockBytes / size);
  if (buffer.size() < per_block * size) buffer.resize(per_block * size);
  ply::RangeStats stats;
  stats.end = range.begin;
  for (std::uint64_t done = 0; done < count; done += per_block) {
    const std::uint64_t n = std::min(per_block, count - done);
    const RecordRange block{range.first_record + done, n, range.begin + done * size, 0};
    records.read(block.begin, std::span(buffer.data(), n * size),
                 {.element = context.layout.element_name});
    ply::RangeStats block_stats =
        ply::decodeFixedRecords(context, buffer.data(), block, n, cloud, first_index + done);
    stats.raw_bounds.extend(block_stats.raw_bounds);
    stats.end = block_stats.end;
  }
  return stats;
}

// Decodes every range into `cloud`. With `records` (a local file's pread source, fixed-size binary
// records only), each range is read by blocks into a buffer of its thread (decodeByBlocks).
DecodeResult decodeAll(const DecodeContext& context, const std::vector<RecordRange>& ranges,
                       PointCloud& cloud, const PlyReadOptions& options,
                       const ByteSource* records) {
  assert((records == nullptr || readsRecordsByRange(context)) &&
         "decodeAll: only fixed-size binary records are read by range");
  std::vector<ply::RangeStats> stats(ranges.size());
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  auto decode = [&](std::size_t i) {
    if (records != nullptr) {
      const RecordRange& range = ranges[i];
      stats[i] = decodeByBlocks(context, *records, range, range.count, cloud, range.first_record,
                                buffers.local());
      if (options.progress) options.progress->advance(range.count);
      return;
    }
    stats[i] = ply::decodeRange(context, ranges[i], ranges[i].count, cloud, ranges[i].first_record);
    // Input pages are released 16 ranges at a time (8 MiB): each release is a system call and a
    // TLB flush on every core. A range of the batch still being decoded just faults its pages in
    // again.
    constexpr std::size_t kBatch = 16;
    if (i % kBatch == kBatch - 1 || i + 1 == ranges.size()) {
      context.releaseRead(ranges[i - i % kBatch].begin, stats[i].end);
    }
    if (options.progress) options.progress->advance(ranges[i].count);
  };
  if (options.parallel) {
    tbb::parallel_for(std::size_t(0), ranges.size(), decode);
  } else {
    for (std::size_t i = 0; i < ranges.size(); ++i) decode(i);
  }
  DecodeResult result;
  for (const auto& s : stats) result.raw_bounds.extend(s.raw_bounds);
  if (!stats.empty()) result.end = stats.back().end;
  return result;
}

// The grid a binary PLY's double positions declare (kPlyQuantizationComment, our writer's), when
// every point lies exactly on it: offset + k * scale, k an int32, computed as the decoders
// quantize and as Quantization::toWorld gives it back. One pass over the positions, only for
// files that carry the comment; any point off the grid (an edited file, chunks written on other
// grids) and the sampled power-of-two grid is used, as for any PLY.
std::optional<Quantization> declaredPlyQuantization(const DecodeContext& context,
                                                    const std::vector<RecordRange>& ranges) {
  const PlyHeader& header = context.header;
  const ply::PointLayout& layout = context.layout;
  if (!readsRecordsByRange(context)) return std::nullopt;
  for (int axis = 0; axis < 3; ++axis) {
    if (layout.properties[std::size_t(layout.position_index[axis])].type != ScalarType::Float64) {
      return std::nullopt;
    }
  }
  Quantization q;
  bool found = false;
  for (const std::string& comment : header.comments) {
    std::string_view text = comment;
    if (!text.starts_with(kPlyQuantizationComment)) continue;
    text.remove_prefix(kPlyQuantizationComment.size());
    double values[6];
    int n = 0;
    for (; n < 6; ++n) {
      while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
      auto result = std::from_chars(text.data(), text.data() + text.size(), values[n]);
      if (result.ec != std::errc() || !std::isfinite(values[n])) break;
      text.remove_prefix(std::size_t(result.ptr - text.data()));
    }
    if (n != 6 || !(values[0] > 0 && values[1] > 0 && values[2] > 0)) return std::nullopt;
    q.scale = {values[0], values[1], values[2]};
    q.offset = {values[3], values[4], values[5]};
    found = true;
  }
  if (!found) return std::nullopt;
  const bool swap = header.format == PlyFormat::BinaryBigEndian;
  std::size_t at[3];
  for (int axis = 0; axis < 3; ++axis) {
    at[axis] = layout.properties[std::size_t(layout.position_index[axis])].byte_offset;
  }
  const double inverse[3] = {1.0 / q.scale[0], 1.0 / q.scale[1], 1.0 / q.scale[2]};
  // The ranges in parallel, as the decode reads them (a serial pass cost half a load again).
  std::atomic<bool> on_grid{true};
  tbb::parallel_for(std::size_t(0), ranges.size(), [&](std::size_t r) {
    const RecordRange& range = ranges[r];
    const std::byte* record = context.bytes.data() + range.begin;
    for (std::uint64_t i = 0; i < range.count && on_grid.load(std::memory_order_relaxed);
         ++i, record += layout.record_size) {
      for (int axis = 0; axis < 3; ++axis) {
        std::uint64_t bits;
        std::memcpy(&bits, record + at[axis], 8);
        if (swap) bits = __builtin_bswap64(bits);  // little-endian host (core/byte_order.h)
        const double v = std::bit_cast<double>(bits);
        const double k = (v - q.offset[axis]) * inverse[axis];
        if (!(k > -2147483648.0 && k < 2147483647.0) ||
            q.toWorld(axis, ply::quantizeClamped(v, q.offset[axis], inverse[axis])) != v) {
          on_grid.store(false, std::memory_order_relaxed);
          break;
        }
      }
    }
  });
  if (!on_grid.load()) return std::nullopt;
  return q;
}

// `path`: the file the bytes were mapped from (nullptr for bytes in memory), read again by range
// where the records allow it.
PointCloud readPlyBytes(std::span<const std::byte> bytes, const std::string& name,
                        const PlyReadOptions& options, const MappedFile* file,
                        const std::filesystem::path* path) {
  PlyHeader header = parsePlyHeader(bytes, name);
  const int point_element = requirePointElement(header, name);
  const PlyElement& element = header.elements[std::size_t(point_element)];
  ply::PointLayout layout = ply::planPointLayout(element, name);
  DecodeContext context{bytes, name, header, layout, file};

  std::vector<RecordRange> ranges = ply::planRanges(context, kRangeBytes, options.parallel);
  const std::optional<Quantization> declared = declaredPlyQuantization(context, ranges);
  Quantization quantization =
      declared ? *declared
               : chooseQuantization(ply::sampleBounds(context, ranges, ply::kQuantizationSamples),
                                    ply::kQuantizationSampleMargin);
  std::unique_ptr<ByteSource> records;
  if (path != nullptr && readsRecordsByRange(context) && std::filesystem::is_regular_file(*path)) {
    records = openFileSource(*path);
  }
  const bool binary_fixed = readsRecordsByRange(context);
  PointCloud cloud =
      ply::allocatePointCloud(layout, element.count, quantization,
                              binary_fixed ? ply::ChannelDefaults::FilledByDecoder
                                           : ply::ChannelDefaults::FilledAtAllocation);
  DecodeResult result = decodeAll(context, ranges, cloud, options, records.get());
  if (header.format == PlyFormat::Ascii) {
    std::size_t end = ranges.empty() ? 0 : result.end;
    std::uint64_t next_line = ranges.empty() ? 0 : ranges.back().first_line + ranges.back().count;
    ply::checkAsciiTail(context, end, next_line);
  }
  if (!fitsQuantization(quantization, result.raw_bounds)) {
    cloud.quantization = chooseQuantization(result.raw_bounds, 1.0);
    PlyReadOptions again = options;
    again.progress = nullptr;
    result = decodeAll(context, ranges, cloud, again, records.get());
  }
  cloud.bounds = quantizedBounds(cloud.quantization, result.raw_bounds);
  return cloud;
}

}  // namespace

PointCloud readPly(const std::filesystem::path& path, const PlyReadOptions& options) {
  MappedFile file(path);
  file.adviseSequential(0, file.size());
  return readPlyBytes(file.bytes(), file.path(), options, &file, &path);
}

PointCloud readPlyFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PlyReadOptions& options) {
  return readPlyBytes(bytes, name, options, nullptr, nullptr);
}

// ---------------------------------------------------------------------------------------------
// Streaming

struct PlyChunkReader::State {
  explicit State(const std::filesystem::path& path)
      : file(path),
        header(parsePlyHeader(file.bytes(), file.path())),
        point_element(requirePointElement(header, file.path())),
        layout(ply::planPointLayout(header.elements[std::size_t(point_element)], file.path())),
        context{file.bytes(), file.path(), header, layout, &file},
        ranges(ply::planRanges(context, kRangeBytes, true)),
        quantization(declaredPlyQuantization(context, ranges)
                         .value_or(chooseQuantization(
                             ply::sampleBounds(context, ranges, ply::kQuantizationSamples),
                             ply::kQuantizationSampleMargin))) {
    if (!ranges.empty()) cursor_byte = ranges.front().begin;
    if (readsRecordsByRange(context) && std::filesystem::is_regular_file(path)) {
      records = openFileSource(path);
    }
  }

  MappedFile file;
  PlyHeader header;
  int point_element;
  ply::PointLayout layout;
  DecodeContext context;
  std::vector<RecordRange> ranges;
  Quantization quantization;
  // Where the next chunk starts: inside ranges[range_index], after `done_in_range` records.
  std::size_t range_index = 0;
  std::uint64_t done_in_range = 0;
  std::size_t cursor_byte = 0;
  std::uint64_t delivered = 0;
  // A local file's fixed-size binary records are read by pread into a buffer of each thread, as
  // readPly reads them (decodeByBlocks); the others through the mapping.
  std::unique_ptr<ByteSource> records;
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
};

PlyChunkReader::PlyChunkReader(const std::filesystem::path& path)
    : state_(std::make_unique<State>(path)) {}
PlyChunkReader::~PlyChunkReader() = default;
PlyChunkReader::PlyChunkReader(PlyChunkReader&&) noexcept = default;

const PlyHeader& PlyChunkReader::header() const {
  return state_->header;
}
std::uint64_t PlyChunkReader::pointCount() const {
  return state_->header.elements[std::size_t(state_->point_element)].count;
}
const Quantization& PlyChunkReader::quantization() const {
  return state_->quantization;
}
void PlyChunkReader::setQuantization(const Quantization& quantization) {
  state_->quantization = quantization;
}

bool PlyChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  assert(max_points > 0 && "PlyChunkReader::next needs a positive max_points");
  State& s = *state_;
  const std::uint64_t remaining = pointCount() - s.delivered;
  if (remaining == 0) {
    chunk = PointCloud{};
    return false;
  }
  const std::uint64_t n = std::min<std::uint64_t>(max_points, remaining);
  chunk = ply::allocatePointCloud(s.layout, n, s.quantization,
                                  readsRecordsByRange(s.context)
                                      ? ply::ChannelDefaults::FilledByDecoder
                                      : ply::ChannelDefaults::FilledAtAllocation);

  // The pieces of ranges this chunk covers; each starts at a known byte, so all decode at once.
  struct Piece {
    RecordRange range;
    std::uint64_t count;
    std::uint64_t dst;
  };
  std::vector<Piece> pieces;
  std::uint64_t filled = 0;
  std::size_t index = s.range_index;
  std::uint64_t skip = s.done_in_range;
  while (filled < n) {
    const RecordRange& range = s.ranges[index];
    RecordRange piece = range;
    piece.first_record += skip;
    piece.count -= skip;
    if (skip > 0) {
      piece.begin = s.cursor_byte;
      if (piece.first_line != 0) piece.first_line += skip;
    }
    std::uint64_t take = std::min(piece.count, n - filled);
    pieces.push_back({piece, take, filled});
    filled += take;
    if (take == piece.count) {
      ++index;
      skip = 0;
    } else {
      skip += take;
    }
  }
  std::vector<ply::RangeStats> stats(pieces.size());
  tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
    const Piece& piece = pieces[i];
    stats[i] = s.records ? decodeByBlocks(s.context, *s.records, piece.range, piece.count, chunk,
                                          piece.dst, s.buffers.local())
                         : ply::decodeRange(s.context, piece.range, piece.count, chunk, piece.dst);
  });
  // The chunk's input pages are read: drop them from the resident set, so that streaming a file
  // larger than memory does not keep all of it mapped in (the page cache keeps them).
  if (!s.records) s.context.releaseRead(pieces.front().range.begin, stats.back().end);
  Bounds3 raw;
  for (const auto& st : stats) raw.extend(st.raw_bounds);
  if (!fitsQuantization(s.quantization, raw)) {
    throw InputError(
        {.file = s.file.path(),
         .element = s.layout.element_name,
         .property = "x, y, z",
         .expected = "points inside the streaming quantization's range",
         .found = "a point outside it in records " + std::to_string(s.delivered) + " to " +
                  std::to_string(s.delivered + n - 1),
         .hint = "the sampled bounds missed outliers; pass exact bounds with setQuantization"});
  }
  s.range_index = index;
  s.done_in_range = skip;
  if (skip > 0) s.cursor_byte = stats.back().end;
  s.delivered += n;
  chunk.bounds = quantizedBounds(s.quantization, raw);
  return true;
}

void PlyChunkReader::skip(std::uint64_t count) {
  State& s = *state_;
  count = std::min(count, pointCount() - s.delivered);
  // Whole ranges first: each knows its first byte (and line), so nothing is read.
  while (count > 0 && s.range_index < s.ranges.size()) {
    const std::uint64_t left = s.ranges[s.range_index].count - s.done_in_range;
    if (count < left) break;
    count -= left;
    s.delivered += left;
    ++s.range_index;
    s.done_in_range = 0;
    if (s.range_index < s.ranges.size()) s.cursor_byte = s.ranges[s.range_index].begin;
  }
  // Inside a range the next record's byte is known only by decoding up to it (ascii lines, binary
  // lists): at most one range is decoded and dropped.
  if (count > 0) {
    PointCloud dropped;
    next(dropped, std::size_t(count));
  }
}

}  // namespace parallax
