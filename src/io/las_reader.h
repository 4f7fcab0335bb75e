// Reading the points of an uncompressed LAS 1.0-1.4 file (point formats 0-10) into the column
// model (LAZ, compressed LAS, through laz_reader.h into the same columns).
//
// Mapping (LAS 1.4 R15 Tables 7-17):
//   X Y Z (int32) + header scale/offset -> positions + quantization, exactly as stored
//   Intensity (uint16)                  -> intensity (float; source.intensity = UInt16)
//   Classification                      -> classification: the 5-bit class for formats 0-5, the
//                                          full 8-bit class for 6-10
//   Red Green Blue (uint16)             -> colors. The rule for 8 bits: when every R, G and B
//                                          value in the file is below 256 the file holds 8-bit
//                                          colours in 16-bit fields (common) and they are kept
//                                          as they are (source.color = UInt8); otherwise each is
//                                          rounded to the nearest of value / 257 (so 65535 ->
//                                          255 and c * 257 -> c; source.color = UInt16).
//                                          That is the display form; the values as stored, 16
//                                          bits whatever their range, are kept in stored_colors,
//                                          which the LAS and LAZ writers give back unchanged.
//   every other field -> a ScalarColumn, in this order and type:
//     return_number, number_of_returns (uint8)
//     formats 0-5:  scan_direction_flag, edge_of_flight_line, classification_flags (uint8),
//                   scan_angle_rank (int8, degrees), user_data (uint8), point_source_id (uint16)
//     formats 6-10: classification_flags, scanner_channel, scan_direction_flag,
//                   edge_of_flight_line, user_data (uint8), scan_angle (int16, 0.006 degree
//                   units), point_source_id (uint16)
//     gps_time (double), nir (uint16),
//     wave packets: wave_packet_descriptor_index (uint8), wave_packet_offset (double: a uint64
//                   byte offset, exact below 2^53), wave_packet_size (uint32),
//                   return_point_waveform_location, waveform_dx, waveform_dy, waveform_dz (float)
//     extra bytes: three float or double ones named as a normal's components (NormalX NormalY
//                   NormalZ as CloudCompare and PDAL write them, nx ny nz, normal_x ...:
//                   las_header.h lasNormalExtraBytes) -> normals (float; source.normal Float64
//                   when all three are doubles); the others
//                   under their VLR names in their types; scaled ones (options bits 3/4) as the
//                   double raw * scale + offset, 64-bit integers as doubles, undocumented bytes
//                   as uint8 columns "<name>_<i>", deprecated arrays as "<name>[i]".
//   classification_flags uses the LAS 1.4 bit layout for every format: bit 0 synthetic, bit 1
//   key-point, bit 2 withheld, bit 3 overlap (formats 0-5 carry only bits 0-2, from the top three
//   bits of their classification byte).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/column_names.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/las_header.h"
#include "io/point_chunk_source.h"

namespace parallax {

// Names of the LAS fields as scalar columns (shared with the writer).
namespace las_names = column_names;

struct LasReadOptions {
  Progress* progress = nullptr;  // advanced by points read
  bool parallel = true;          // all cores (TBB); false runs on the calling thread only
};

// Reads every point: the records are read through per-thread buffers of a block each (pread), so
// the process holds the columns and a few MB, never the file's pages. A LAZ file (the header
// says so) is read by readLaz (laz_reader.h). Throws InputError for malformed input (see
// parseLasHeader).
PointCloud readLas(const std::filesystem::path& path, const LasReadOptions& options = {});

// About `max_points` points of a large LAS or LAZ file for a first picture: runs of 64
// consecutive records at even steps through the file (LAZ: readLazPreview). Colours follow the
// 8-bit rule over the sample. The whole file when it has at most `max_points` points.
PointCloud readLasPreview(const std::filesystem::path& path, std::uint64_t max_points);

// The same from bytes in memory (tests, fuzzing); `name` stands for the file in messages.
PointCloud readLasFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const LasReadOptions& options = {});

// Streams the points of a LAS file in chunks, in file order, holding only one chunk. The
// quantization is the header's, so every chunk holds the file's exact integers.
class LasChunkReader final : public PointChunkSource {
 public:
  explicit LasChunkReader(const std::filesystem::path& path);
  ~LasChunkReader() override;
  LasChunkReader(LasChunkReader&&) noexcept;

  const LasHeader& header() const;
  std::uint64_t pointCount() const override;
  const CoordinateSystem& crs() const override;  // the header's projection records
  const Quantization& quantization() const override;

  // Replaces `chunk` with the next at most `max_points` points (`max_points` > 0); false (and an
  // empty chunk) at the end.
  bool next(PointCloud& chunk, std::size_t max_points) override;
  // Steps over the next `count` points (fewer at the end): records have a fixed size, so the
  // next chunk starts `count` records later without reading them.
  bool canSkip() const override { return true; }
  void skip(std::uint64_t count) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
