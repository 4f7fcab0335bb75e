// Reading PCD files (the Point Cloud Library's format; the header is described in pcd_header.h)
// into the column model: DATA ascii, binary and binary_compressed, any fields.
//
// Mapping (pcd_decoder.h): x y z -> positions (any type; the quantization is chosen from the
// exact bounds of the valid points, so every float32 position and most float64 ones are held
// exactly: core/quantization.h); rgb / rgba packed in 4 bytes (float or uint32, 0xAARRGGBB) ->
// colours; normal_x normal_y normal_z -> normals; intensity -> intensity; any other field -> a
// scalar column under its name and type (64-bit integers as doubles), a field of COUNT n as n
// columns "name_0" ... "name_{n-1}"; PCL's padding fields "_" skipped.
//
// Invalid points: PCL marks a point it has no measurement for (an organised cloud's empty
// pixels) with NaN coordinates; points whose x, y or z is not finite are skipped, so the cloud
// holds fewer points than POINTS. An organised cloud (HEIGHT > 1) becomes an unorganised one:
// its WIDTH and HEIGHT stay in the header (PcdChunkReader::header()).
//
// VIEWPOINT, the sensor's position and orientation, is in the header (PcdHeader::viewpoint) for
// code that needs the sensor (orienting normals towards it).
//
// Memory: binary files are mapped and decoded straight into the columns, in parallel; ascii
// values go through a table of doubles a chunk at a time; binary_compressed is decompressed
// whole (LZF has no independent blocks) into one buffer beside the columns.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/pcd_header.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct PcdReadOptions {
  Progress* progress = nullptr;  // advanced by records read
  bool parallel = true;
};

// Reads every valid point. Throws InputError naming the file and the line (header, ascii data)
// or byte offset (binary data) and the field, for a malformed header (pcd_header.h), data shorter
// than POINTS records, an ascii line with the wrong number of values or a value that is not a
// number of its field's type, compressed sizes that do not fit, LZF data that does not
// decompress.
PointCloud readPcd(const std::filesystem::path& path, const PcdReadOptions& options = {});

// The same from bytes in memory; `name` stands for the file in messages.
PointCloud readPcdFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PcdReadOptions& options = {});

// Streams the valid points in chunks, in file order. The quantization is fixed before the first
// chunk, from a first pass over the positions (exact bounds), or given by the caller.
class PcdChunkReader final : public PointChunkSource {
 public:
  // Throws InputError as readPcd does for the header and the data's size.
  explicit PcdChunkReader(const std::filesystem::path& path,
                          const Quantization* quantization = nullptr);
  ~PcdChunkReader() override;
  PcdChunkReader(PcdChunkReader&&) noexcept;

  const PcdHeader& header() const;
  // Valid points (the file's POINTS less those with NaN coordinates).
  std::uint64_t pointCount() const override;
  const Quantization& quantization() const override;
  // Replaces `chunk` with the next at most `max_points` points (`max_points` > 0); false (and an
  // empty chunk) at the end. Throws InputError for a bad ascii line.
  bool next(PointCloud& chunk, std::size_t max_points) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
