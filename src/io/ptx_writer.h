// Writing PointClouds as PTX (ptx_reader.h) and PTS files.
//
// PTX: one scan per value of the "scan_index" column (in increasing order; one scan when the
// cloud has none), each a grid of 1 row of n columns, in world coordinates: the transform is the
// identity and the scanner pose that of `scans[index]` when given, else at the origin with the
// identity axes. Point lines are x y z intensity [r g b] (intensity 0 when the cloud has none):
// positions with the fewest digits that read back to the same double. A point at exactly
// (0, 0, 0) cannot be written (PTX reads it as "no return"): std::invalid_argument.
#pragma once

#include <filesystem>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/ptx_reader.h"

namespace parallax {

struct PtxWriteOptions {
  Progress* progress = nullptr;                 // advanced by points written
  const std::vector<PtxScan>* scans = nullptr;  // poses by scan index (readPtx's), when known
};

// Writes to a temporary file beside `path`, renamed at the end. Throws std::runtime_error on I/O
// failure.
void writePtx(const PointCloud& cloud, const std::filesystem::path& path,
              const PtxWriteOptions& options = {});

}  // namespace parallax
