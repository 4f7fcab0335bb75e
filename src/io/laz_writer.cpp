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

std::uint64_t writeLazPointData(OutputFile& out, std::uint64_t data_offset,
                                const laz::LaszipVlr& vlr, std::uint64_t count,
                                const LasRecordFiller& records, Progress* progress) {
  auto makeEncoder = [&vlr]() -> std::unique_ptr<laz::ChunkEncoder> {
    try {
      return vlr.compressor == 3 ? laz::makeLayeredEncoder(vlr.items)
                                 : laz::makePointwiseEncoder(vlr.items);
    } catch (const laz::UnsupportedItems& e) {
      throw std::runtime_error(std::string("LAZ writer: ") + e.what() + "; write .las instead");
    }
  };
  makeEncoder();  // fail before anything is written when the codec is missing
  const std::size_t length = vlr.recordLength();
  const std::uint64_t chunk_points = vlr.chunk_size;
  std::vector<laz::LazChunk> table;
  std::uint64_t position = data_offset;
  const std::uint64_t placeholder = 0;  // the table's offset, written at the end
  out.write(&placeholder, 8);
  position += 8;

  struct Local {
    std::unique_ptr<laz::ChunkEncoder> encoder;
    std::vector<std::byte> records;
  };
  tbb::enumerable_thread_specific<Local> locals;
  // A batch of chunks in flight: two per core keeps them busy while the batch is written.
  const std::size_t batch = std::size_t(2 * tbb::this_task_arena::max_concurrency());
  std::vector<std::vector<std::uint8_t>> compressed(batch);
  const std::uint64_t chunks = (count + chunk_points - 1) / chunk_points;
  for (std::uint64_t first_chunk = 0; first_chunk < chunks; first_chunk += batch) {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(batch, chunks - first_chunk));
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
      Local& local = locals.local();
      if (!local.encoder) local.encoder = makeEncoder();
      const std::uint64_t first = (first_chunk + k) * chunk_points;
      const std::size_t points = std::size_t(std::min(chunk_points, count - first));
      local.records.resize(points * length);
      records(first, points, local.records.data());
      compressed[k].clear();
      local.encoder->encode(local.records.data(), points, compressed[k]);
    });
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint64_t first = (first_chunk + k) * chunk_points;
      const std::uint64_t points = std::min(chunk_points, count - first);
      if (compressed[k].size() > UINT32_MAX) {
        throw std::runtime_error("LAZ writer: a chunk of " + std::to_string(points) +
                                 " points compressed to over 4 GiB; use smaller chunks");
      }
      out.write(compressed[k].data(), compressed[k].size());
      table.push_back({.offset = position,
                       .bytes = compressed[k].size(),
                       .first_point = first,
                       .points = points});
      position += compressed[k].size();
      if (progress) progress->advance(points);
    }
  }
  // The chunk table (LAZ specification): version 0, the count, the sizes' stream.
  const std::uint32_t header[2] = {0, std::uint32_t(table.size())};
  out.write(header, sizeof header);
  const std::vector<std::uint8_t> stream =
      laz::encodeChunkTable(table, vlr.chunk_size == laz::kVariableChunkSize);
  out.write(stream.data(), stream.size());
  out.writeAt(data_offset, &position, 8);
  return position + sizeof header + stream.size();
}

void writeLaz(const PointCloud& cloud, const std::filesystem::path& path,
              const LazWriteOptions& options) {
  assert(options.chunk_points > 0 && "LAZ chunks hold at least one point");
  LasWriteOptions las = options.las;
  las.laz_chunk_points = options.chunk_points;
  writeLas(cloud, path, las);
}

}  // namespace parallax
