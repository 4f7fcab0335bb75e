#include "io/laz_reader.h"

#include <sys/stat.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cstring>
#include <exception>
#include <limits>
#include <map>
#include <mutex>

#include "core/byte_source_opener.h"
#include "core/error.h"
#include "io/las_record_decoder.h"
#include "io/laz_source.h"
#include "io/mapped_file.h"

namespace parallax {
namespace {

using DecoderPool = tbb::enumerable_thread_specific<std::unique_ptr<LazChunkDecoder>>;

// The calling thread's decoder, decoding the field groups `fields` (LasDecodePlan::laz_fields).
LazChunkDecoder& decoderOf(DecoderPool& pool, const LazSource& source, std::uint32_t fields) {
  std::unique_ptr<LazChunkDecoder>& decoder = pool.local();
  if (!decoder) decoder = std::make_unique<LazChunkDecoder>(source, fields);
  return *decoder;
}

// Decodes the chunks `indices` (in parallel, or in order on this thread for a sequential source
// or `parallel` false) and calls fn(index, records) for each. When chunks fail, the error of the
// one earliest in the file is thrown, so a damaged file always reports the same first point.
template <class F>
void forEachChunk(LazSource& source, DecoderPool& pool, std::uint32_t fields,
                  const std::vector<std::size_t>& indices, bool parallel, F fn) {
  if (source.sequential || !parallel || indices.size() < 2) {
    for (std::size_t index : indices) {
      fn(index, decoderOf(pool, source, fields).decode(source, index));
    }
    return;
  }
  std::mutex error_mutex;
  std::size_t error_index = std::numeric_limits<std::size_t>::max();
  std::exception_ptr error;
  std::atomic<std::size_t> failed{std::numeric_limits<std::size_t>::max()};
  tbb::parallel_for(std::size_t(0), indices.size(), [&](std::size_t k) {
    const std::size_t index = indices[k];
    if (index > failed.load(std::memory_order_relaxed)) return;
    try {
      fn(index, decoderOf(pool, source, fields).decode(source, index));
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (index < error_index) {
        error_index = index;
        error = std::current_exception();
        failed = index;
      }
    }
  });
  if (error) std::rethrow_exception(error);
}

std::vector<std::size_t> range(std::size_t first, std::size_t last) {
  std::vector<std::size_t> indices;
  for (std::size_t i = first; i < last; ++i) indices.push_back(i);
  return indices;
}

PointCloud readSource(LazSource& s, const LazReadOptions& options) {
  LasDecodePlan plan = makeLasDecodePlan(s.records, options.attributes);
  const std::size_t count = s.records.point_count;
  PointCloud cloud = allocateLasCloud(s.records, plan, count);
  if (s.chunks.empty()) return cloud;
  s.planChunkReads(range(0, s.chunks.size()));
  DecoderPool pool;
  LasDecodeStats stats;
  std::mutex stats_mutex;
  // The first chunk settles the colours of most files (a value of 256 or more there: 16-bit);
  // otherwise the decode guesses 8-bit and checks every colour on the way.
  {
    const std::byte* records = decoderOf(pool, s, plan.laz_fields).decode(s, 0);
    const std::size_t n = s.chunks[0].points;
    plan.colors_8bit = !lasColorsAbove255(records, n, plan);
    decodeLasRecords(records, n, plan, cloud, 0, stats);
    if (options.progress) options.progress->advance(n);
  }
  forEachChunk(s, pool, plan.laz_fields, range(1, s.chunks.size()), options.parallel,
               [&](std::size_t index, const std::byte* records) {
                 const laz::LazChunk& chunk = s.chunks[index];
                 LasDecodeStats local;
                 decodeLasRecords(records, chunk.points, plan, cloud, chunk.first_point, local);
                 if (options.progress) options.progress->advance(chunk.points);
                 const std::lock_guard lock(stats_mutex);
                 stats.merge(local);
               });
  if (plan.colors_8bit && stats.color_above_255) {
    // Rare: 8-bit colours in the first chunk, 16-bit ones later. Decode again for the colours.
    plan.colors_8bit = false;
    s.planChunkReads(range(0, s.chunks.size()));
    forEachChunk(s, pool, plan.laz_fields, range(0, s.chunks.size()), options.parallel,
                 [&](std::size_t index, const std::byte* records) {
                   const laz::LazChunk& chunk = s.chunks[index];
                   decodeLasColors(records, chunk.points, plan, cloud, chunk.first_point);
                 });
  }
  cloud.source.color = plan.colors_8bit ? ScalarType::UInt8 : ScalarType::UInt16;
  cloud.bounds = stats.world(cloud.quantization);
  return cloud;
}

std::unique_ptr<LazSource> openFile(const std::filesystem::path& path) {
  std::unique_ptr<ByteSource> in = openLasSource(path);  // a URL: the chunks by range
  LasHeader header = readLasHeader(*in);
  if (!header.laszip) {
    throw InputError({.file = path.string(),
                      .byte_offset = 104,
                      .element = "header",
                      .property = "point data format",
                      .expected = "a LAZ file (LASzip's compression bit in the point format)",
                      .found = "an uncompressed LAS file",
                      .hint = "read it as LAS"});
  }
  return openLazSource(std::move(in), std::move(header));
}

// Which colour rule later streams of a file use, once a stream found 16-bit values that its
// sample did not show (see LazChunkReader in laz_reader.h). Keyed by path, size and time.
std::mutex g_memo_mutex;
std::map<std::string, bool> g_colors_16bit;

std::string fileKey(const std::filesystem::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return {};
  return std::filesystem::absolute(path).string() + "|" + std::to_string(info.st_size) + "|" +
         std::to_string(info.st_mtim.tv_sec) + "." + std::to_string(info.st_mtim.tv_nsec);
}

}  // namespace

PointCloud readLaz(const std::filesystem::path& path, const LazReadOptions& options) {
  if (!isUrl(path.string()) && !std::filesystem::is_regular_file(path)) {
    const MappedFile file(path);  // a pipe or a special file: read whole first
    return readLazFromMemory(file.bytes(), path.string(), options);
  }
  std::unique_ptr<LazSource> source = openFile(path);
  return readSource(*source, options);
}

PointCloud readLazFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const LazReadOptions& options) {
  LasHeader header = parseLasHeader(bytes, name);
  if (!header.laszip) {
    throw InputError({.file = name,
                      .byte_offset = 104,
                      .element = "header",
                      .property = "point data format",
                      .expected = "a LAZ file",
                      .found = "an uncompressed LAS file"});
  }
  std::unique_ptr<LazSource> source =
      openLazSource(viewMemorySource(bytes, name), std::move(header));
  return readSource(*source, options);
}

PointCloud readLazPreview(const std::filesystem::path& path, std::uint64_t max_points) {
  std::unique_ptr<LazSource> source = openFile(path);
  LazSource& s = *source;
  if (s.records.point_count <= max_points || s.chunks.size() < 2) return readSource(s, {});
  // Whole chunks (a chunk decodes only from its start), spread evenly, about twice the points
  // wanted, every k-th kept. A file whose chunks must be found in order gives its first ones.
  const std::uint64_t decode_points =
      std::min<std::uint64_t>(2 * max_points, s.records.point_count);
  const std::uint64_t per_chunk = std::max<std::uint64_t>(1, s.chunks[0].points);
  const std::size_t wanted = std::size_t(
      std::clamp<std::uint64_t>((decode_points + per_chunk - 1) / per_chunk, 1, s.chunks.size()));
  std::vector<std::size_t> indices;
  for (std::size_t k = 0; k < wanted; ++k) {
    const std::size_t index = s.sequential ? k : k * s.chunks.size() / wanted;
    if (indices.empty() || indices.back() != index) indices.push_back(index);
  }
  std::uint64_t decoded = 0;
  for (std::size_t index : indices) decoded += s.chunks[index].points;
  const std::uint64_t stride = std::max<std::uint64_t>(1, (decoded + max_points - 1) / max_points);
  std::vector<std::uint64_t> first(indices.size() + 1, 0);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    first[k + 1] = first[k] + (s.chunks[indices[k]].points + stride - 1) / stride;
  }
  LasDecodePlan plan = makeLasDecodePlan(s.records);
  PointCloud cloud = allocateLasCloud(s.records, plan, first.back());
  s.planChunkReads(indices);
  DecoderPool pool;
  // Colours: 16-bit as soon as one sampled chunk says so; sampled chunks are decoded once, so
  // the rule comes from a first pass over the first chunk and is checked after.
  LasDecodeStats stats;
  std::mutex stats_mutex;
  std::vector<std::byte> kept;
  const std::size_t length = s.records.record_length;
  auto keep = [&](std::size_t k, const std::byte* records, std::vector<std::byte>& out) {
    const std::size_t n = std::size_t(first[k + 1] - first[k]);
    out.resize(n * length);
    for (std::size_t i = 0; i < n; ++i) {
      std::memcpy(out.data() + i * length, records + i * stride * length, length);
    }
    return n;
  };
  tbb::enumerable_thread_specific<std::vector<std::byte>> buffers;
  std::vector<std::size_t> order(indices.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::map<std::size_t, std::size_t> slot_of;
  for (std::size_t k = 0; k < indices.size(); ++k) slot_of[indices[k]] = k;
  forEachChunk(s, pool, plan.laz_fields, indices, true,
               [&](std::size_t index, const std::byte* records) {
                 const std::size_t k = slot_of[index];
                 std::vector<std::byte>& buffer = buffers.local();
                 const std::size_t n = keep(k, records, buffer);
                 LasDecodeStats local;
                 decodeLasRecords(buffer.data(), n, plan, cloud, first[k], local);
                 const std::lock_guard lock(stats_mutex);
                 stats.merge(local);
               });
  if (stats.color_above_255) {
    plan.colors_8bit = false;
    s.planChunkReads(indices);
    forEachChunk(s, pool, plan.laz_fields, indices, true,
                 [&](std::size_t index, const std::byte* records) {
                   const std::size_t k = slot_of[index];
                   std::vector<std::byte>& buffer = buffers.local();
                   const std::size_t n = keep(k, records, buffer);
                   decodeLasColors(buffer.data(), n, plan, cloud, first[k]);
                 });
  }
  cloud.source.color = plan.colors_8bit ? ScalarType::UInt8 : ScalarType::UInt16;
  cloud.bounds = stats.world(cloud.quantization);
  return cloud;
}

LazSummary summarizeLaz(const std::filesystem::path& path) {
  std::unique_ptr<LazSource> source = openFile(path);
  const LazSource& s = *source;
  LazSummary summary;
  summary.compressor = s.vlr.compressor;
  summary.compressor_name = s.vlr.compressor == 1   ? "point-wise"
                            : s.vlr.compressor == 2 ? "point-wise chunked"
                                                    : "layered chunked";
  summary.chunk_size = s.vlr.chunk_size == laz::kVariableChunkSize ? 0 : s.vlr.chunk_size;
  summary.chunks = s.chunks.size();
  summary.laszip_version = std::to_string(s.vlr.version_major) + "." +
                           std::to_string(s.vlr.version_minor) + "." +
                           std::to_string(s.vlr.version_revision);
  static const char* const kNames[] = {"BYTE",     "SHORT",        "INTEGER", "LONG",
                                       "FLOAT",    "DOUBLE",       "POINT10", "GPSTIME11",
                                       "RGB12",    "WAVEPACKET13", "POINT14", "RGB14",
                                       "RGBNIR14", "WAVEPACKET14", "BYTE14"};
  for (const laz::LazItem& item : s.vlr.items) {
    const unsigned type = unsigned(item.type);
    summary.items.push_back(std::string(type < 15 ? kNames[type] : "unknown") + " v" +
                            std::to_string(item.version) + " (" + std::to_string(item.size) +
                            " bytes)");
  }
  summary.compatibility_mode = s.compatibility.has_value();
  summary.record_format = s.records.point_format;
  summary.table_note = s.table_note;
  return summary;
}

// ---------------------------------------------------------------------------------------------

struct LazChunkReader::State {
  std::unique_ptr<LazSource> source;
  std::string key;
  LasDecodePlan plan;
  DecoderPool pool;
  std::size_t next_chunk = 0;
  std::uint64_t emitted = 0;
  // The part of a chunk not handed out yet (a batch ended inside it).
  std::vector<std::byte> pending, spare;
  std::size_t pending_count = 0, pending_taken = 0;
  CoordinateSystem crs;  // of the records' header (1.4's in compatibility mode)
};

LazChunkReader::LazChunkReader(const std::filesystem::path& path,
                               const AttributeSelection& attributes)
    : state_(std::make_unique<State>()) {
  State& st = *state_;
  st.source = openFile(path);
  LazSource& s = *st.source;
  st.key = fileKey(path);
  st.plan = makeLasDecodePlan(s.records, attributes);
  st.crs = coordinateSystemOf(s.records);
  if (!st.plan.color_offset || s.chunks.empty()) return;
  {
    const std::lock_guard lock(g_memo_mutex);
    if (auto found = g_colors_16bit.find(st.key); found != g_colors_16bit.end()) {
      st.plan.colors_8bit = !found->second;
      return;
    }
  }
  // A sample of chunks: the first, the middle and the last (only the first when the chunks must
  // be found in order).
  std::vector<std::size_t> sample = {0};
  if (!s.sequential && s.chunks.size() > 1) {
    if (s.chunks.size() > 2) sample.push_back(s.chunks.size() / 2);
    sample.push_back(s.chunks.size() - 1);
  }
  std::atomic<bool> big{false};
  forEachChunk(s, st.pool, st.plan.laz_fields, sample, true,
               [&](std::size_t index, const std::byte* records) {
                 if (lasColorsAbove255(records, s.chunks[index].points, st.plan)) big = true;
               });
  st.plan.colors_8bit = !big;
}

LazChunkReader::~LazChunkReader() = default;
LazChunkReader::LazChunkReader(LazChunkReader&&) noexcept = default;

const LasHeader& LazChunkReader::header() const {
  return state_->source->records;
}
const CoordinateSystem& LazChunkReader::crs() const {
  return state_->crs;
}
std::uint64_t LazChunkReader::pointCount() const {
  return state_->source->records.point_count;
}
const Quantization& LazChunkReader::quantization() const {
  return state_->source->records.quantization;
}

bool LazChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  assert(max_points > 0 && "LazChunkReader::next needs a positive chunk size");
  State& st = *state_;
  LazSource& s = *st.source;
  const std::size_t n =
      std::size_t(std::min<std::uint64_t>(max_points, s.records.point_count - st.emitted));
  chunk = allocateLasCloud(s.records, st.plan, n);
  if (n == 0) return false;
  const std::size_t length = s.records.record_length;
  const std::size_t start_chunk = st.next_chunk;
  const std::size_t start_count = st.pending_count, start_taken = st.pending_taken;
  bool new_pending = false;

  auto fill = [&] {
    LasDecodeStats stats;
    std::mutex stats_mutex;
    std::size_t filled = 0;
    if (st.pending_taken < st.pending_count) {
      const std::size_t k = std::min(n, st.pending_count - st.pending_taken);
      decodeLasRecords(st.pending.data() + st.pending_taken * length, k, st.plan, chunk, 0, stats);
      st.pending_taken += k;
      filled = k;
    }
    // Whole chunks that fit, in parallel.
    const std::size_t first_chunk = st.next_chunk;
    std::size_t last_chunk = first_chunk;
    std::size_t whole = filled;
    while (last_chunk < s.chunks.size() && whole + s.chunks[last_chunk].points <= n) {
      whole += std::size_t(s.chunks[last_chunk++].points);
    }
    // This batch's chunks and the one it may end inside, hinted for a remote file.
    s.planChunkReads(range(first_chunk, std::min(last_chunk + 1, s.chunks.size())));
    if (last_chunk > first_chunk) {
      const std::uint64_t base = s.chunks[first_chunk].first_point;
      forEachChunk(s, st.pool, st.plan.laz_fields, range(first_chunk, last_chunk), true,
                   [&](std::size_t index, const std::byte* records) {
                     const laz::LazChunk& c = s.chunks[index];
                     LasDecodeStats local;
                     decodeLasRecords(records, c.points, st.plan, chunk,
                                      filled + std::size_t(c.first_point - base), local);
                     const std::lock_guard lock(stats_mutex);
                     stats.merge(local);
                   });
    }
    filled = whole;
    st.next_chunk = last_chunk;
    // The start of the next chunk; the rest of it is kept for the next batch (the chunk it
    // replaces stays in `spare`, in case this batch is decoded again).
    if (filled < n && st.next_chunk < s.chunks.size()) {
      const laz::LazChunk& c = s.chunks[st.next_chunk];
      const std::byte* records = decoderOf(st.pool, s, st.plan.laz_fields).decode(s, st.next_chunk);
      st.spare.assign(records, records + std::size_t(c.points) * length);
      std::swap(st.pending, st.spare);
      new_pending = true;
      st.pending_count = std::size_t(c.points);
      const std::size_t k = std::min(n - filled, st.pending_count);
      decodeLasRecords(st.pending.data(), k, st.plan, chunk, filled, stats);
      st.pending_taken = k;
      filled += k;
      ++st.next_chunk;
    }
    if (filled != n) {
      throw InputError({.file = s.in->name(),
                        .element = "LAZ chunks",
                        .expected = std::to_string(s.records.point_count) + " points",
                        .found = "chunks holding fewer"});
    }
    return stats;
  };

  LasDecodeStats stats = fill();
  if (st.plan.colors_8bit && stats.color_above_255) {
    // The sample missed 16-bit colours: this batch is decoded again with the 16-bit rule, which
    // holds from here on, and for later streams of this file.
    st.plan.colors_8bit = false;
    chunk.source.color = ScalarType::UInt16;
    {
      const std::lock_guard lock(g_memo_mutex);
      if (!st.key.empty()) g_colors_16bit[st.key] = true;
    }
    if (new_pending) std::swap(st.pending, st.spare);
    st.next_chunk = start_chunk;
    st.pending_count = start_count;
    st.pending_taken = start_taken;
    stats = fill();
  }
  st.emitted += n;
  chunk.bounds = stats.world(chunk.quantization);
  return true;
}

}  // namespace parallax
