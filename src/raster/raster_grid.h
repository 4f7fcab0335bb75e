// The geometry of an elevation raster: a north-up grid of square cells over the cloud's x-y
// plane, and the rule that puts a point in a cell.
//
// Cell rule: cells are half-open squares [left + c R, left + (c+1) R) x [bottom + k R,
// bottom + (k+1) R): a point on a vertical edge belongs to the cell at its right, a point on a
// horizontal edge to the cell above it. Rows count from the top (GeoTIFF's north-up order): row
// r holds k = rows - 1 - r. Without --bounds the edges are aligned to multiples of R,
// left = floor(minx / R) R and bottom = floor(miny / R) R, and the grid reaches far enough that
// the largest x and y fall inside (so a cloud with maxx on a multiple of R gets one more column
// holding only its right-most points). With --bounds the edges start at the given minimum and
// the grid holds ceil((max - min) / R) cells; points outside are left out.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "core/bounds.h"

namespace parallax {

struct RasterGrid {
  double left = 0.0;        // x of the left edge of column 0
  double top = 0.0;         // y of the top edge of row 0
  double resolution = 1.0;  // cell size in x and y (positive)
  std::int64_t columns = 0;
  std::int64_t rows = 0;

  double bottom() const { return top - double(rows) * resolution; }
  double right() const { return left + double(columns) * resolution; }
  std::uint64_t cellCount() const { return std::uint64_t(columns) * std::uint64_t(rows); }

  // GDAL's affine transform: x = gt[0] + col gt[1], y = gt[3] + row gt[5] (corner of the cell).
  std::array<double, 6> geoTransform() const {
    return {left, resolution, 0.0, top, 0.0, -resolution};
  }
  // The centre of cell (column, row).
  double centreX(std::int64_t column) const { return left + (double(column) + 0.5) * resolution; }
  double centreY(std::int64_t row) const { return top - (double(row) + 0.5) * resolution; }

  // The column of x by the cell rule (may be outside [0, columns)).
  std::int64_t columnOf(double x) const {
    return static_cast<std::int64_t>(std::floor((x - left) / resolution));
  }
  // The row of y by the cell rule (may be outside [0, rows)).
  std::int64_t rowOf(double y) const {
    const double bottom_edge = bottom();
    return rows - 1 - static_cast<std::int64_t>(std::floor((y - bottom_edge) / resolution));
  }
};

// The grid covering [minx, maxx] x [miny, maxy] with edges on multiples of `resolution` (the
// cell rule above). `resolution` must be positive and the bounds finite.
// Throws std::invalid_argument (naming --resolution) when a side would pass GeoTIFF's 2^31 - 1
// cells; this and boundedGrid.
RasterGrid alignedGrid(double minx, double miny, double maxx, double maxy, double resolution);

// The grid with its lower-left corner at (minx, miny) and ceil((max - min) / R) cells a side
// (--bounds): at least one cell.
RasterGrid boundedGrid(double minx, double miny, double maxx, double maxy, double resolution);

// Throws std::invalid_argument (naming --resolution) when the grid is more 256 x 256 tiles than
// a GeoTIFF's tile index holds (2^28: libtiff's 2 GB of offsets, as GDAL checks it, whose own
// message named neither the option nor the cause). A grid to be written by GeoTiffWriter.
void checkGeoTiffTiles(const RasterGrid& grid);

// Whether two grids are the same cells (same size and, within a millionth of a cell, the same
// corner and resolution): rasters that can be subtracted cell by cell.
bool sameGrid(const RasterGrid& a, const RasterGrid& b);

}  // namespace parallax
