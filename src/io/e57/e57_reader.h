// Reading E57 files (ASTM E2807) into the column model.
//
// Every scan (child of /data3D) is read, in file order, its points moved into the file's frame by
// the scan's pose (rotation quaternion, then translation). Fields of the point record:
//   cartesianX Y Z, or sphericalRange Azimuth Elevation (radians; x = r cos(el) cos(az),
//   y = r cos(el) sin(az), z = r sin(el))                -> positions (int32, quantized)
//   cartesianInvalidState / sphericalInvalidState != 0   -> the point is skipped (1 means only a
//                                                           direction is known, 2 nothing)
//   colorRed Green Blue -> colors: mapped from the scan's colorLimits (else the field's own
//     range) onto 0..255, so a file of 0..255 colours is kept exactly; source.color says whether
//     the file's range was 8 or 16 bits (or wider)
//   intensity -> intensity: mapped from intensityLimits (else the field's range) onto 0..65535,
//     the range LAS gives intensity; kept as stored when neither gives a range (both 0, as
//     CloudCompare writes them)
//   isColorInvalid, isIntensityInvalid != 0 -> that point's colour or intensity is 0
//   any other number field (rowIndex, columnIndex, returnIndex, returnCount, timeStamp, ...)
//                          -> a scalar column of that name: int32 when every scan's Integer range
//                             fits it, else float64 (0 in scans without the field)
//   and always "scan_index" (uint32): the 0-based scan the point came from. The scans' poses
//   (their positions, for orienting normals towards the scanner) are in header().document.
// Images (/images2D) are listed in the header, not decoded.
//
// Memory: the file is mapped and read through its checksummed pages a packet at a time; one
// chunk of columns is held, whatever the file's size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/column_names.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/e57/e57_document.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct E57Header {
  std::uint32_t version_major = 1;
  std::uint32_t version_minor = 0;
  // The records of every scan (recordCount). Invalid points are skipped while reading, so the
  // points delivered can be fewer.
  std::uint64_t record_count = 0;
  // Bounds of the points in the file's frame: from the scans' cartesianBounds (or sphericalBounds'
  // rangeMaximum, or the fields' declared ranges) moved by their poses when every scan states one,
  // else measured by a pass over the positions (bounds_measured).
  Bounds3 bounds;
  bool bounds_measured = false;
  bool has_colors = false;
  bool has_intensity = false;
  std::vector<std::string> attributes;  // as PointCloud::attributeNames() of the chunks
  E57Document document;
};

struct E57ReadOptions {
  Progress* progress = nullptr;  // advanced by records read
};

// True when `bytes` (the start of a file) begin with the E57 signature "ASTM-E57".
bool looksLikeE57(std::span<const std::byte> bytes);

// Reads every valid point of every scan. Throws InputError naming the file and the byte offset
// (a page's, a packet's, the XML section's) or the XML element and line for malformed input:
// a bad checksum, a truncated file, XML that is not well formed, a missing field.
PointCloud readE57(const std::filesystem::path& path, const E57ReadOptions& options = {});
PointCloud readE57FromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const E57ReadOptions& options = {});

// The first points of each scan, about `max_points` in all (a compressed vector can only be
// decoded from its start, so this is no spread sample; it costs what those points cost).
PointCloud readE57Preview(const std::filesystem::path& path, std::uint64_t max_points);

// Streams the points in chunks: the scans in file order, each from its start.
class E57ChunkReader final : public PointChunkSource {
 public:
  explicit E57ChunkReader(const std::filesystem::path& path);
  // From bytes in memory (they must outlive the reader); `name` stands for the file in messages.
  E57ChunkReader(std::span<const std::byte> bytes, const std::string& name);
  ~E57ChunkReader() override;
  E57ChunkReader(E57ChunkReader&&) noexcept;

  const E57Header& header() const;
  std::uint64_t pointCount() const override;  // header().record_count
  // Chosen from header().bounds; a point outside it is an InputError naming the scan and record
  // (declared bounds that lie), which setQuantization() with wider bounds avoids.
  const Quantization& quantization() const override;
  void setQuantization(const Quantization& quantization);
  // Replaces header().bounds with bounds measured by a pass over every position (each record's
  // position fields decoded, the rest stepped over) and the quantization with one chosen from them.
  void measureBounds();
  // Advanced by records decoded; may be null.
  void setProgress(Progress* progress);

  // Replaces `chunk` with the next at most `max_points` valid points (`max_points` > 0); false
  // (and an empty chunk) at the end.
  bool next(PointCloud& chunk, std::size_t max_points) override;

  // From now on, at most `records` records of each scan are decoded (the rest of a scan is
  // stepped over undecoded): for previews.
  void limitRecordsPerScan(std::uint64_t records);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
