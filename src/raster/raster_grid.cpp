#include "raster/raster_grid.h"

#include <cassert>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace parallax {

namespace {

// GeoTIFF's limit on a side (ImageWidth and ImageLength are 32-bit; GDAL takes an int). Above it
// the count is refused before it becomes an integer: a resolution of 1e-300 made 1e303 cells a
// side, out of int64's range (undefined; it came out negative and an empty raster was written).
constexpr double kMaxCellsASide = 2147483647.0;

std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

std::int64_t checkedCells(double cells, double extent, double resolution, const char* axis) {
  if (!(cells <= kMaxCellsASide)) {
    throw std::invalid_argument(
        "--resolution " + shortNumber(resolution) + ": the extent of " + shortNumber(extent) +
        " in " + axis + " makes " + shortNumber(cells) +
        " cells, over GeoTIFF's 2147483647 a side: expected a resolution of at least " +
        shortNumber(extent / (kMaxCellsASide - 1.0)));
  }
  return static_cast<std::int64_t>(cells);
}

// Cells from `origin` to past `max`: floor((max - origin) / R) + 1, so that `max` itself falls
// in the last one (the cell rule puts a point on an edge in the cell above or to its right).
std::int64_t cellsReaching(double origin, double max, double resolution, const char* axis) {
  return checkedCells(std::floor((max - origin) / resolution) + 1.0, max - origin, resolution,
                      axis);
}

}  // namespace

RasterGrid alignedGrid(double minx, double miny, double maxx, double maxy, double resolution) {
  assert(resolution > 0.0 && "alignedGrid: the resolution must be positive");
  RasterGrid grid;
  grid.resolution = resolution;
  grid.left = std::floor(minx / resolution) * resolution;
  const double bottom = std::floor(miny / resolution) * resolution;
  grid.columns = cellsReaching(grid.left, maxx, resolution, "x");
  grid.rows = cellsReaching(bottom, maxy, resolution, "y");
  grid.top = bottom + double(grid.rows) * resolution;
  return grid;
}

RasterGrid boundedGrid(double minx, double miny, double maxx, double maxy, double resolution) {
  assert(resolution > 0.0 && "boundedGrid: the resolution must be positive");
  RasterGrid grid;
  grid.resolution = resolution;
  grid.left = minx;
  grid.columns = std::max<std::int64_t>(
      1, checkedCells(std::ceil((maxx - minx) / resolution), maxx - minx, resolution, "x"));
  grid.rows = std::max<std::int64_t>(
      1, checkedCells(std::ceil((maxy - miny) / resolution), maxy - miny, resolution, "y"));
  grid.top = miny + double(grid.rows) * resolution;
  return grid;
}

void checkGeoTiffTiles(const RasterGrid& grid) {
  // GeoTiffWriter's tiles (geotiff.cpp: BLOCKXSIZE, BLOCKYSIZE 256), and libtiff's limit on the
  // tile index that GDAL's GTiff driver enforces: its offsets and byte counts, 8 bytes a tile
  // in a BigTIFF (any raster this large is one), under 2 GB, so at most 2^28 tiles.
  constexpr double kTileSide = 256.0;
  constexpr double kMaxTiles = 268435456.0;
  const double tiles =
      std::ceil(double(grid.columns) / kTileSide) * std::ceil(double(grid.rows) / kTileSide);
  if (tiles > kMaxTiles) {
    throw std::invalid_argument(
        "--resolution " + shortNumber(grid.resolution) + ": the grid of " +
        std::to_string(grid.columns) + " x " + std::to_string(grid.rows) + " cells is " +
        shortNumber(tiles) +
        " tiles of 256 x 256, over the 268435456 a GeoTIFF's tile index holds: expected a "
        "resolution of at least " +
        shortNumber(grid.resolution * std::sqrt(tiles / kMaxTiles)));
  }
}

bool sameGrid(const RasterGrid& a, const RasterGrid& b) {
  if (a.columns != b.columns || a.rows != b.rows) return false;
  const double tolerance = 1e-6 * a.resolution;
  return std::abs(a.resolution - b.resolution) <= tolerance &&
         std::abs(a.left - b.left) <= tolerance && std::abs(a.top - b.top) <= tolerance;
}

}  // namespace parallax
