#include "raster/volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "core/point_filter.h"
#include "io/point_file.h"
#include "raster/geotiff.h"
#include "raster/raster_fill.h"

namespace parallax {

namespace {

// The surface at the centres of the cells the ring crosses, each cell once.
std::vector<std::array<double, 3>> boundarySamples(const RasterImage& surface,
                                                   const Polygon2& ring) {
  const RasterGrid& grid = surface.grid;
  std::set<std::pair<std::int64_t, std::int64_t>> seen;
  std::vector<std::array<double, 3>> samples;
  const double step = grid.resolution / 4.0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const auto& p = ring[i];
    const auto& q = ring[(i + 1) % ring.size()];
    const double length = std::hypot(q[0] - p[0], q[1] - p[1]);
    const auto steps = std::max<std::int64_t>(1, std::int64_t(std::ceil(length / step)));
    for (std::int64_t k = 0; k < steps; ++k) {
      const double t = double(k) / double(steps);
      const double x = p[0] + t * (q[0] - p[0]), y = p[1] + t * (q[1] - p[1]);
      const std::int64_t column = grid.columnOf(x), row = grid.rowOf(y);
      if (column < 0 || column >= grid.columns || row < 0 || row >= grid.rows) continue;
      if (!seen.insert({column, row}).second || !surface.hasValue(column, row)) continue;
      samples.push_back({grid.centreX(column), grid.centreY(row), surface.at(column, row)});
    }
  }
  return samples;
}

}  // namespace

bool fitPlane(const std::vector<std::array<double, 3>>& samples, double& a, double& b, double& c) {
  if (samples.size() < 3) return false;
  // Centred on the samples' mean, so that UTM-sized coordinates keep their precision.
  double mx = 0, my = 0, mz = 0;
  for (const auto& s : samples) mx += s[0], my += s[1], mz += s[2];
  const double n = double(samples.size());
  mx /= n, my /= n, mz /= n;
  double sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
  for (const auto& s : samples) {
    const double dx = s[0] - mx, dy = s[1] - my, dz = s[2] - mz;
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxz += dx * dz, syz += dy * dz;
  }
  const double det = sxx * syy - sxy * sxy;
  if (!(std::abs(det) > 1e-12 * std::max(1.0, sxx * syy))) return false;
  a = (sxz * syy - syz * sxy) / det;
  b = (syz * sxx - sxz * sxy) / det;
  c = mz - a * mx - b * my;
  return true;
}

VolumeReport computeVolume(const VolumeOptions& options) {
  if (!(options.resolution > 0.0) || !std::isfinite(options.resolution)) {
    throw std::invalid_argument("--resolution: expected a positive number of units a cell, found " +
                                std::to_string(options.resolution));
  }
  if (options.surface != RasterValue::Max && options.surface != RasterValue::Mean) {
    throw std::invalid_argument("--surface: expected max or mean");
  }
  if (options.polygon.size() < 3) throw std::invalid_argument("--polygon: at least 3 vertices");
  double minx = std::numeric_limits<double>::infinity(), miny = minx, maxx = -minx, maxy = -minx;
  for (const auto& v : options.polygon) {
    minx = std::min(minx, v[0]), maxx = std::max(maxx, v[0]);
    miny = std::min(miny, v[1]), maxy = std::max(maxy, v[1]);
  }
  VolumeReport report;
  report.grid = alignedGrid(minx, miny, maxx, maxy, options.resolution);
  const RasterGrid& grid = report.grid;

  RasterReport counts;
  RasterImage surface;
  surface.grid = grid;
  surface.values = rasterizeRows(options.input, grid, options.surface, options.resolution, 0,
                                 grid.rows, surface.nodata, counts);
  report.points_used = counts.points_used;
  report.cells_filled =
      fillNodata(surface, options.fill_radius > 0.0 ? options.fill_radius
                                                    : kDefaultFillCells * options.resolution);

  // The base at each cell's centre.
  RasterImage base_raster;
  if (options.base == VolumeBase::Raster) {
    base_raster = readRaster(options.base_raster);
  } else {
    const auto samples = boundarySamples(surface, options.polygon);
    report.boundary_samples = samples.size();
    if (options.base == VolumeBase::Plane) {
      if (!fitPlane(samples, report.plane_a, report.plane_b, report.plane_c)) {
        throw std::invalid_argument(
            "--base plane: the surface along the polygon's ring gives " +
            std::to_string(samples.size()) +
            " samples, not enough for a plane (no points under the ring? try --base lowest)");
      }
    } else {
      if (samples.empty()) {
        throw std::invalid_argument(
            "--base lowest: the cloud has no points under the polygon's ring");
      }
      double lowest = samples.front()[2];
      for (const auto& s : samples) lowest = std::min(lowest, s[2]);
      report.plane_c = lowest;
    }
  }

  PointFilter inside;
  inside.polygon = options.polygon;
  RasterImage difference;
  difference.grid = grid;
  difference.values.assign(grid.cellCount(), difference.nodata);
  const double cell_area = grid.resolution * grid.resolution;
  for (std::int64_t row = 0; row < grid.rows; ++row) {
    const double y = grid.centreY(row);
    for (std::int64_t column = 0; column < grid.columns; ++column) {
      const double x = grid.centreX(column);
      if (!inside.insidePolygon(x, y)) continue;
      if (!surface.hasValue(column, row)) {
        ++report.cells_without_surface;
        continue;
      }
      double base = 0.0;
      if (options.base == VolumeBase::Raster) {
        const std::int64_t bc = base_raster.grid.columnOf(x), br = base_raster.grid.rowOf(y);
        if (bc < 0 || bc >= base_raster.grid.columns || br < 0 || br >= base_raster.grid.rows ||
            !base_raster.hasValue(bc, br)) {
          ++report.cells_without_base;
          continue;
        }
        base = base_raster.at(bc, br);
      } else {
        base = report.plane_a * x + report.plane_b * y + report.plane_c;
      }
      const double d = double(surface.at(column, row)) - base;
      if (d > 0) {
        report.cut += d * cell_area;
      } else {
        report.fill -= d * cell_area;
      }
      ++report.cells;
      difference.at(column, row) = float(d);
    }
  }
  report.net = report.cut - report.fill;
  report.area = double(report.cells) * cell_area;
  if (!options.raster_out.empty()) {
    difference.wkt = wktOfCoordinateSystem(readPointFileHeader(options.input.path).crs);
    writeGeoTiff(difference, options.raster_out);
  }
  return report;
}

}  // namespace parallax
