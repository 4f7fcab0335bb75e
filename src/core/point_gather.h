// Copies of some records of a point cloud, every column carried: by an index list or a range.
// Shared by the in-memory octree (records in octree order, node slices) and the point filter.
#pragma once

#include <cstdint>
#include <span>

#include "core/point_cloud.h"

namespace parallax {

// The points of `cloud` at `indices`, in that order, with every attribute (parallel; bounds left
// empty).
PointCloud gatherPoints(const PointCloud& cloud, std::span<const std::uint32_t> indices);
PointCloud gatherPoints(const PointCloud& cloud, std::span<const std::uint64_t> indices);

// The records [first, first + count) of `cloud` (bounds left empty).
PointCloud slicePoints(const PointCloud& cloud, std::uint64_t first, std::uint64_t count);

}  // namespace parallax
