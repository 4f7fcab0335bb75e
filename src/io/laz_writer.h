// Writing LAZ: the LAS file las_writer.h describes (same header, VLRs, records), its point data
// compressed as LASzip does it:
//   point formats 0-3 (LAS 1.2): compressor 2, point-wise chunked, items POINT10, GPSTIME11,
//     RGB12 and BYTE (the extra bytes) at version 2;
//   point formats 6-8 (LAS 1.4): compressor 3, layered chunked, items POINT14, RGB14 / RGBNIR14
//     and BYTE14 at version 3;
// chunks of a fixed number of points (50 000 by default, LASzip's) and a chunk table after them.
// Chunks are encoded on every core, a batch at a time, and written in file order; the file
// appears under its name only when complete. Decoded by any LAZ reader, the file gives exactly
// the records writeLas would have written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>

#include "core/point_cloud.h"
#include "io/las_writer.h"
#include "io/laz/chunk_codec.h"

namespace parallax {

class OutputFile;

inline constexpr std::uint32_t kDefaultLazChunkPoints = 50000;

struct LazWriteOptions {
  LasWriteOptions las;                                  // the LAS layout, VLRs, progress
  std::uint32_t chunk_points = kDefaultLazChunkPoints;  // > 0
};

// Throws std::runtime_error on I/O failure and when the codec of the point format is missing.
void writeLaz(const PointCloud& cloud, const std::filesystem::path& path,
              const LazWriteOptions& options = {});

// The "laszip encoded" VLR for records of `point_format` and `record_length` bytes.
laz::LaszipVlr makeLaszipVlr(int point_format, std::size_t record_length,
                             std::uint32_t chunk_points);

// Fills `n` records from point `first` on (thread-safe: called for several chunks at once).
using LasRecordFiller = std::function<void(std::uint64_t first, std::size_t n, std::byte* out)>;

// Writes the LAZ point data of `count` points at the end of `out`: the chunk table offset (at
// `data_offset`, the current end), the chunks, the table; returns the offset of the end of the
// table (where EVLRs may follow). Used by the LAS writer.
std::uint64_t writeLazPointData(OutputFile& out, std::uint64_t data_offset,
                                const laz::LaszipVlr& vlr, std::uint64_t count,
                                const LasRecordFiller& records, Progress* progress);

}  // namespace parallax
