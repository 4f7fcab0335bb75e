// Writing E57 files (ASTM E2807): the pages with their CRC-32C, one compressed vector section a
// scan (bit-packed bytestreams in data packets of at most 64 KiB, then one index packet, as the
// standard asks), and the XML section last.
//
// writeE57 writes a cloud as one scan: positions as ScaledInteger fields with the cloud's own
// scale and offset (every int32 position kept exactly) or as doubles, colour as 8-bit Integer
// fields with colorLimits 0..255, intensity as a float field with intensityLimits 0..65535 (what
// the reader maps back onto itself) or, for values outside that range, no limits (kept as stored).
// writeE57Scans writes any scans given field by field (several scans, poses, spherical
// coordinates, invalid states): the tests' and benchmarks' way to make files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/e57/e57_document.h"

namespace parallax {

struct E57WriteOptions {
  Progress* progress = nullptr;  // advanced by points written
  // Positions as ScaledInteger fields (exact, 4 bytes a coordinate or less) or as doubles.
  bool scaled_integer_positions = true;
  std::string scan_name = "scan 0";
};

// Writes `cloud` as one scan. Normals, classification and other scalar columns are not written
// (describeE57Losses). Throws std::runtime_error on I/O failure; the file appears under its name
// only when complete.
void writeE57(const PointCloud& cloud, const std::filesystem::path& path,
              const E57WriteOptions& options = {});

// What writeE57 drops of `cloud`, one phrase each.
std::vector<std::string> describeE57Losses(const PointCloud& cloud);

// One scan to write: its prototype (fields in bytestream order: Integer and ScaledInteger with
// minimum and maximum raw values, ScaledInteger with scale and offset, Float with its precision;
// `bits` is computed by the writer), and a function filling `values[field]` with the values of
// records [first, first + count) (Integer: the integer; ScaledInteger: the value, stored as the
// nearest raw integer; Float: the value).
struct E57ScanSource {
  std::string name;
  E57Pose pose;
  std::vector<E57Field> fields;
  std::uint64_t record_count = 0;
  std::function<void(std::uint64_t first, std::size_t count,
                     std::vector<std::vector<double>>& values)>
      fill;
  std::optional<Bounds3> cartesian_bounds;  // in the scan's frame
  std::optional<double> range_maximum;      // sphericalBounds
  std::optional<std::array<double, 2>> intensity_limits;
  std::optional<std::array<double, 6>> color_limits;
};

void writeE57Scans(std::span<const E57ScanSource> scans, const std::filesystem::path& path,
                   Progress* progress = nullptr);

}  // namespace parallax
