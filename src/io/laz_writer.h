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
#include <memory>

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

// The LAZ point data of a LAS file whose records arrive in order, a block at a time: the chunk
// table offset (at `data_offset`, the current end of `out`), then each chunk of
// vlr.chunk_size points compressed as soon as a batch of them (two a core) is complete, encoded
// on every core and written in file order, then the table. Holds at most one batch of records
// and its compressed chunks, whatever the point count. Used by the LAS writer (las_writer.h).
class LazPointDataWriter {
 public:
  // Throws std::runtime_error when the codec of the VLR's items is missing, before any write.
  LazPointDataWriter(OutputFile& out, std::uint64_t data_offset, const laz::LaszipVlr& vlr,
                     Progress* progress);
  ~LazPointDataWriter();
  LazPointDataWriter(const LazPointDataWriter&) = delete;
  LazPointDataWriter& operator=(const LazPointDataWriter&) = delete;

  // Appends `n` records of vlr.recordLength() bytes each.
  void add(const std::byte* records, std::size_t n);
  // Compresses what is left (the last chunk may be short), writes the chunk table and its offset;
  // returns the offset of the end of the table (where EVLRs may follow).
  std::uint64_t finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
