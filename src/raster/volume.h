// Cut, fill and net volume between a cloud's surface and a base inside a polygon (`parallax
// volume`): a stockpile, a pit, earthworks between two epochs.
//
// The surface is a raster of the cloud on a grid aligned to the resolution over the polygon's
// bounding box (raster_grid.h): the highest point of each cell (or the mean, --surface mean, for
// a dense cloud: the highest point of a cell lies up the slope from its centre by up to half a
// cell, which adds about gradient x R / 2 over a pile's footprint), gaps filled by inverse
// distance (raster_fill.h, 10 cells). Only the cells whose centre is inside the polygon
// (even-odd rule) count, each its area R^2 times (surface - base) at its centre.
//   cut  = sum of the positive differences (material above the base: what would be removed)
//   fill = sum of the negative ones, as a positive number (space below the base)
//   net  = cut - fill
// The base:
//   plane   the least-squares plane z = a x + b y + c through the surface along the polygon's
//           ring: every cell the ring crosses (walked at steps of R / 4), once, at its centre
//   lowest  the horizontal plane at the lowest of those samples
//   FILE    a raster (a DTM, an earlier epoch), sampled at each cell's centre (the cell of the
//           base raster holding it); cells where it has no value are left out and counted.
//           It must be in the cloud's CRS where both state one (GDAL's OSRIsSame; a file
//           without a CRS is taken as it is), and its extent must hold every counted cell's
//           centre: a polygon reaching past the raster is an error, not a smaller volume, and so
//           is a raster without a value at any cell inside the polygon.
// `parallax volume` and the viewer's Volume tool (src/viewer/volume_tool.cpp) both call
// computeVolume, with the base set by setVolumeBase: the same checks, the same figures.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "io/polygon_reader.h"
#include "raster/raster_builder.h"

namespace parallax {

enum class VolumeBase { Plane, Lowest, Raster };

struct VolumeOptions {
  RasterInput input;
  Polygon2 polygon;
  double resolution = 0.5;
  RasterValue surface = RasterValue::Max;  // Max or Mean
  VolumeBase base = VolumeBase::Plane;
  std::filesystem::path base_raster;  // VolumeBase::Raster
  double fill_radius = 0.0;           // 0 = 10 cells
  // When set, the raster of surface - base inside the polygon (nodata outside) is written here.
  std::filesystem::path raster_out;
};

struct VolumeReport {
  double cut = 0.0, fill = 0.0, net = 0.0;
  double area = 0.0;  // of the cells counted
  std::uint64_t cells = 0;
  std::uint64_t cells_filled = 0;           // surface gaps filled
  std::uint64_t cells_without_surface = 0;  // inside, no value even after filling: left out
  std::uint64_t cells_without_base = 0;     // inside, the base raster has no value: left out
  std::uint64_t boundary_samples = 0;
  double plane_a = 0.0, plane_b = 0.0, plane_c = 0.0;  // the base plane (plane, lowest)
  RasterGrid grid;
  std::uint64_t points_used = 0;
};

// The base as `--base` names it: "plane", "lowest", or else the path of a raster file
// (VolumeBase::Raster; computeVolume checks that it is one).
void setVolumeBase(VolumeOptions& options, const std::string& base);

// Throws std::invalid_argument naming `option` (--base, view's --volume-base) when `file`, a base
// raster's path, is not a file: computeVolume's first check, which a caller can make early.
void requireBaseRasterFile(const std::string& option, const std::filesystem::path& file);

// Throws std::invalid_argument naming the option (--base for a base raster that is not a file),
// InputError for bad input files: one GDAL cannot read, a base raster in another CRS than the
// cloud's, one that does not cover the polygon or has no value inside it (naming the raster).
VolumeReport computeVolume(const VolumeOptions& options);

// The least-squares plane z = a x + b y + c of the samples (at least 3, not on one line); false
// when they do not determine one.
bool fitPlane(const std::vector<std::array<double, 3>>& samples, double& a, double& b, double& c);

}  // namespace parallax
