#include "raster/raster_grid.h"

#include <cassert>
#include <cmath>

namespace parallax {

namespace {

// Cells from `origin` to past `max`: floor((max - origin) / R) + 1, so that `max` itself falls
// in the last one (the cell rule puts a point on an edge in the cell above or to its right).
std::int64_t cellsReaching(double origin, double max, double resolution) {
  return static_cast<std::int64_t>(std::floor((max - origin) / resolution)) + 1;
}

}  // namespace

RasterGrid alignedGrid(double minx, double miny, double maxx, double maxy, double resolution) {
  assert(resolution > 0.0 && "alignedGrid: the resolution must be positive");
  RasterGrid grid;
  grid.resolution = resolution;
  grid.left = std::floor(minx / resolution) * resolution;
  const double bottom = std::floor(miny / resolution) * resolution;
  grid.columns = cellsReaching(grid.left, maxx, resolution);
  grid.rows = cellsReaching(bottom, maxy, resolution);
  grid.top = bottom + double(grid.rows) * resolution;
  return grid;
}

RasterGrid boundedGrid(double minx, double miny, double maxx, double maxy, double resolution) {
  assert(resolution > 0.0 && "boundedGrid: the resolution must be positive");
  RasterGrid grid;
  grid.resolution = resolution;
  grid.left = minx;
  grid.columns = std::max<std::int64_t>(1, std::int64_t(std::ceil((maxx - minx) / resolution)));
  grid.rows = std::max<std::int64_t>(1, std::int64_t(std::ceil((maxy - miny) / resolution)));
  grid.top = miny + double(grid.rows) * resolution;
  return grid;
}

bool sameGrid(const RasterGrid& a, const RasterGrid& b) {
  if (a.columns != b.columns || a.rows != b.rows) return false;
  const double tolerance = 1e-6 * a.resolution;
  return std::abs(a.resolution - b.resolution) <= tolerance &&
         std::abs(a.left - b.left) <= tolerance && std::abs(a.top - b.top) <= tolerance;
}

}  // namespace parallax
