#include "io/laz_writer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cassert>
#include <memory>
#include <vector>

#include <stdexcept>

#include "io/las_header.h"
#include "io/laz/layered_codec.h"
#include "io/laz/laz_layout.h"
#include "io/laz/pointwise_codec.h"
#include "io/point_file.h"

namespace parallax {

laz::LaszipVlr makeLaszipVlr(int point_format, std::size_t record_length,
                             std::uint32_t chunk_points) {
  assert(chunk_points > 0 && "a LAZ chunk holds at least one point");
  using laz::ItemType;
  laz::LaszipVlr vlr;
  // The LASzip release whose format this is (3.4 wrote the same streams); readers only check
  // the compressor and the items.
  vlr.version_major = 3;
  vlr.version_minor = 4;
  vlr.version_revision = 3;
  vlr.chunk_size = chunk_points;
  const bool layered = point_format >= 6;
  vlr.compressor = layered ? 3 : 2;
  const std::uint16_t version = layered ? 3 : 2;
  std::size_t used = lasPointFormatSize(point_format);
  if (layered) {
    vlr.items.push_back({ItemType::Point14, 30, version});
    if (lasFormatHasNir(point_format)) {
      vlr.items.push_back({ItemType::RgbNir14, 8, version});
    } else if (lasFormatHasColor(point_format)) {
      vlr.items.push_back({ItemType::Rgb14, 6, version});
    }
    if (lasFormatHasWavePacket(point_format)) {
      vlr.items.push_back({ItemType::Wavepacket14, 29, version});
    }
  } else {
    vlr.items.push_back({ItemType::Point10, 20, version});
    if (lasFormatHasGpsTime(point_format)) vlr.items.push_back({ItemType::GpsTime11, 8, version});
    if (lasFormatHasColor(point_format)) vlr.items.push_back({ItemType::Rgb12, 6, version});
    if (lasFormatHasWavePacket(point_format)) {
      vlr.items.push_back({ItemType::Wavepacket13, 29, 1});
    }
  }
  if (record_length > used) {
    vlr.items.push_back({layered ? ItemType::Byte14 : ItemType::Byte,
                         std::uint16_t(record_length - used), version});
  }
  return vlr;
}

struct LazPointDataWriter::State {
  OutputFile& out;
  std::uint64_t data_offset = 0;
  laz::LaszipVlr vlr;
  Progress* progress = nullptr;
  std::size_t length = 0;          // bytes a record
  std::size_t chunk_points = 0;    // points a chunk
  std::size_t batch = 0;           // chunks compressed at once
  std::uint64_t position = 0;      // where the next chunk goes
  std::uint64_t points = 0;        // records compressed so far
  std::vector<std::byte> pending;  // records of the batch being filled
  std::vector<laz::LazChunk> table;
  struct Local {
    std::unique_ptr<laz::ChunkEncoder> encoder;
  };
  tbb::enumerable_thread_specific<Local> locals;
  std::vector<std::vector<std::uint8_t>> compressed;

  State(OutputFile& file, const laz::LaszipVlr& laszip) : out(file), vlr(laszip) {}

  std::unique_ptr<laz::ChunkEncoder> makeEncoder() const {
    try {
      return vlr.compressor == 3 ? laz::makeLayeredEncoder(vlr.items)
                                 : laz::makePointwiseEncoder(vlr.items);
    } catch (const laz::UnsupportedItems& e) {
      throw std::runtime_error(std::string("LAZ writer: ") + e.what() + "; write .las instead");
    }
  }

  // Compresses the pending records (whole chunks, and a short last one only at the end) on
  // every core and writes them in order.
  void flush() {
    const std::size_t count = pending.size() / length;
    const std::size_t n = (count + chunk_points - 1) / chunk_points;
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
      Local& local = locals.local();
      if (!local.encoder) local.encoder = makeEncoder();
      const std::size_t first = k * chunk_points;
      const std::size_t size = std::min(chunk_points, count - first);
      compressed[k].clear();
      local.encoder->encode(pending.data() + first * length, size, compressed[k]);
    });
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint64_t size = std::min(chunk_points, count - k * chunk_points);
      if (compressed[k].size() > UINT32_MAX) {
        throw std::runtime_error("LAZ writer: a chunk of " + std::to_string(size) +
                                 " points compressed to over 4 GiB; use smaller chunks");
      }
      out.write(compressed[k].data(), compressed[k].size());
      table.push_back({.offset = position,
                       .bytes = compressed[k].size(),
                       .first_point = points,
                       .points = size});
      position += compressed[k].size();
      points += size;
      if (progress) progress->advance(size);
    }
    pending.clear();
  }
};

LazPointDataWriter::LazPointDataWriter(OutputFile& out, std::uint64_t data_offset,
                                       const laz::LaszipVlr& vlr, Progress* progress)
    : state_(std::make_unique<State>(out, vlr)) {
  assert(vlr.chunk_size != laz::kVariableChunkSize &&
         "the LAZ writer writes chunks of a fixed size");
  State& s = *state_;
  s.makeEncoder();  // fail before anything is written when the codec is missing
  s.data_offset = data_offset;
  s.progress = progress;
  s.length = vlr.recordLength();
  s.chunk_points = vlr.chunk_size;
  // A batch of chunks in flight: two per core keeps them busy while the batch is written.
  s.batch = std::size_t(2 * tbb::this_task_arena::max_concurrency());
  s.compressed.resize(s.batch);
  const std::uint64_t placeholder = 0;  // the table's offset, written at the end
  out.write(&placeholder, 8);
  s.position = data_offset + 8;
}

LazPointDataWriter::~LazPointDataWriter() = default;

void LazPointDataWriter::add(const std::byte* records, std::size_t n) {
  State& s = *state_;
  const std::size_t full = s.batch * s.chunk_points * s.length;
  std::size_t bytes = n * s.length;
  while (bytes > 0) {
    const std::size_t take = std::min(bytes, full - s.pending.size());
    s.pending.insert(s.pending.end(), records, records + take);
    records += take;
    bytes -= take;
    if (s.pending.size() == full) s.flush();
  }
}

std::uint64_t LazPointDataWriter::finish() {
  State& s = *state_;
  if (!s.pending.empty()) s.flush();
  // The chunk table (LAZ specification): version 0, the count, the sizes' stream.
  const std::uint32_t header[2] = {0, std::uint32_t(s.table.size())};
  s.out.write(header, sizeof header);
  const std::vector<std::uint8_t> stream =
      laz::encodeChunkTable(s.table, s.vlr.chunk_size == laz::kVariableChunkSize);
  s.out.write(stream.data(), stream.size());
  s.out.writeAt(s.data_offset, &s.position, 8);
  return s.position + sizeof header + stream.size();
}

void writeLaz(const PointCloud& cloud, const std::filesystem::path& path,
              const LazWriteOptions& options) {
  assert(options.chunk_points > 0 && "LAZ chunks hold at least one point");
  LasWriteOptions las = options.las;
  las.laz_chunk_points = options.chunk_points;
  writeLas(cloud, path, las);
}

}  // namespace parallax
