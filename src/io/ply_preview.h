// A quick look at a large PLY file: a sample of its points spread evenly over the whole point
// element, read in a fraction of the time the whole file takes, so a viewer can show a first
// picture while the level-of-detail octree is built.
#pragma once

#include <cstdint>
#include <filesystem>

#include "core/point_cloud.h"

namespace parallax {

// At most about `max_points` points (every point when the file has no more): runs of
// consecutive records taken at even steps through the point element, so the sample has the
// file's spatial coverage with some local density. Columns, quantization and errors as readPly
// (an error in a record the sample skips is not seen). Binary bodies are addressed directly;
// an ascii body is scanned once for its line starts.
PointCloud readPlyPreview(const std::filesystem::path& path, std::uint64_t max_points);

}  // namespace parallax
