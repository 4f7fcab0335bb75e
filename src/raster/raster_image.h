// A float32 raster held whole in memory: the grid, its values row-major from the top row, the
// value of cells without one, and the CRS (OGC WKT, empty for none).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "raster/raster_grid.h"

namespace parallax {

// The nodata value Parallax writes: far below any elevation on Earth, and what gdal_grid and
// most DEM tools use.
inline constexpr float kRasterNodata = -9999.0f;

struct RasterImage {
  RasterGrid grid;
  std::vector<float> values;  // grid.rows * grid.columns
  float nodata = kRasterNodata;
  std::string wkt;

  float at(std::int64_t column, std::int64_t row) const {
    return values[std::size_t(row) * std::size_t(grid.columns) + std::size_t(column)];
  }
  float& at(std::int64_t column, std::int64_t row) {
    return values[std::size_t(row) * std::size_t(grid.columns) + std::size_t(column)];
  }
  bool hasValue(std::int64_t column, std::int64_t row) const { return at(column, row) != nodata; }
};

}  // namespace parallax
