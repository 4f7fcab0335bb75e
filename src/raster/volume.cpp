#include "raster/volume.h"

#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>

#include "core/error.h"
#include "core/point_filter.h"
#include "io/partial_output.h"
#include "io/point_file.h"
#include "raster/geotiff.h"
#include "raster/raster_fill.h"

namespace parallax {

namespace {

// The grid is held whole (no --memory bands): the surface's accumulator, the surface, its copy
// in fillNodata and the difference raster. Refused above the machine's physical memory, before
// any allocation: at --resolution 1e-4 over a 500 x 1000 polygon (5e13 cells) the allocation
// failed with a bare "out of memory", and under AddressSanitizer (over its 1 TB allocation
// limit) aborted; a grid under that limit but over the memory would be killed by the kernel.
void checkVolumeGridFits(const RasterGrid& grid, const VolumeOptions& options) {
  const double bytes = double(grid.columns) * double(grid.rows) *
                       double(CellAccumulator::bytesPerCell(options.surface) + 3 * sizeof(float));
  const double memory = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
  if (memory > 0 && bytes > memory) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "--resolution %g: the polygon's bounding box (%g x %g) makes %lld x %lld cells, "
                  "%.0f MB held whole, over this machine's %.0f MB of memory: expected a "
                  "coarser resolution (at least %.3g)",
                  options.resolution, double(grid.columns) * grid.resolution,
                  double(grid.rows) * grid.resolution, static_cast<long long>(grid.columns),
                  static_cast<long long>(grid.rows), bytes / 1048576.0, memory / 1048576.0,
                  options.resolution * std::sqrt(bytes / memory));
    throw std::invalid_argument(text);
  }
}

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

// The base raster, read and checked against the cloud: the file is there, GDAL reads it, and
// its CRS is the cloud's where both state one.
RasterImage readBaseRaster(const VolumeOptions& options) {
  requireBaseRasterFile("--base", options.base_raster);
  RasterImage raster = readRaster(options.base_raster);
  if (!raster.wkt.empty()) {
    const std::string cloud = wktOfCoordinateSystem(readPointFileHeader(options.input.path).crs);
    if (!cloud.empty() && !sameCoordinateSystem(raster.wkt, cloud)) {
      InputErrorInfo info;
      info.file = options.base_raster.string();
      info.element = "base raster";
      info.property = "CRS";
      info.expected = "the cloud's CRS, " + coordinateSystemName(cloud);
      info.found = coordinateSystemName(raster.wkt);
      info.hint = "reproject the raster to the cloud's CRS (gdalwarp -t_srs)";
      throw InputError(info);
    }
  }
  return raster;
}

std::string rangeText(double low, double high) {
  char text[96];
  std::snprintf(text, sizeof text, "[%.10g, %.10g]", low, high);
  return text;
}

// Every cell of `grid` whose centre is inside the polygon has its centre within the base
// raster's extent: a base over part of the polygon would give the volume of that part only,
// which reads like the whole's. Throws InputError naming the raster, its extent and the cells'.
void checkBaseCovers(const RasterImage& base, const RasterGrid& grid,
                     const VolumeOptions& options) {
  PointFilter inside;
  inside.polygon = options.polygon;
  std::uint64_t beyond = 0;
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (std::int64_t row = 0; row < grid.rows; ++row) {
    const double y = grid.centreY(row);
    const std::int64_t br = base.grid.rowOf(y);
    for (std::int64_t column = 0; column < grid.columns; ++column) {
      const double x = grid.centreX(column);
      const std::int64_t bc = base.grid.columnOf(x);
      if (bc >= 0 && bc < base.grid.columns && br >= 0 && br < base.grid.rows) continue;
      if (!inside.insidePolygon(x, y)) continue;
      ++beyond;
      min_x = std::min(min_x, x), max_x = std::max(max_x, x);
      min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    }
  }
  if (beyond == 0) return;
  const RasterGrid& b = base.grid;
  InputErrorInfo info;
  info.file = options.base_raster.string();
  info.element = "base raster";
  info.property = "extent";
  info.expected = "a raster covering the polygon";
  info.found = "x " + rangeText(b.left, b.left + double(b.columns) * b.resolution) + ", y " +
               rangeText(b.top - double(b.rows) * b.resolution, b.top) + ", and " +
               std::to_string(beyond) + " cell centres inside the polygon beyond it (x " +
               rangeText(min_x, max_x) + ", y " + rangeText(min_y, max_y) + ")";
  info.hint = "give a base raster over the whole polygon, or a polygon inside the raster";
  throw InputError(info);
}

}  // namespace

void requireBaseRasterFile(const std::string& option, const std::filesystem::path& file) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw std::invalid_argument(option + ": expected plane, lowest or a raster file, found '" +
                                file.string() + "' (no such file)");
  }
}

void setVolumeBase(VolumeOptions& options, const std::string& base) {
  if (base == "plane") {
    options.base = VolumeBase::Plane;
  } else if (base == "lowest") {
    options.base = VolumeBase::Lowest;
  } else {
    options.base = VolumeBase::Raster;
    options.base_raster = base;
  }
}

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
  // The raster's path before the work, as raster checks -o: a missing folder failed in GDAL after
  // the whole computation.
  if (!options.raster_out.empty()) {
    requireOutputIsNotInput(options.raster_out, options.input.path, "--raster-out", "GeoTIFF");
    requireOutputFolder(options.raster_out, "--raster-out");
  }
  // 0 is the default (10 cells); a negative or non-finite radius is a mistake, as for raster.
  if (options.fill_radius < 0.0 || !std::isfinite(options.fill_radius)) {
    throw std::invalid_argument("--fill-radius: expected a positive distance, found " +
                                std::to_string(options.fill_radius));
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
  checkVolumeGridFits(grid, options);

  // A base raster first: a wrong one is said before the cloud is read.
  RasterImage base_raster;
  if (options.base == VolumeBase::Raster) {
    base_raster = readBaseRaster(options);
    checkBaseCovers(base_raster, grid, options);
  }

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
  if (options.base != VolumeBase::Raster) {
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
        assert(bc >= 0 && bc < base_raster.grid.columns && br >= 0 && br < base_raster.grid.rows &&
               "computeVolume: checkBaseCovers let a cell beyond the base raster through");
        if (!base_raster.hasValue(bc, br)) {
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
  if (options.base == VolumeBase::Raster && report.cells == 0 && report.cells_without_base > 0) {
    InputErrorInfo info;
    info.file = options.base_raster.string();
    info.element = "base raster";
    info.property = "values";
    info.expected = "a value at the polygon's cells";
    info.found = "nodata at all " + std::to_string(report.cells_without_base) + " of them";
    throw InputError(info);
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
