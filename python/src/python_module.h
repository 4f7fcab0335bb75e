// The pieces of the Python module `parallax` (module.cpp puts them together), and the object the
// Python `PointCloud` wraps.
//
// Ownership: a Python PointCloud holds a shared CloudHandle; every numpy array it hands out has
// that Python object as its base, so the C++ columns live as long as any array over them.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/column.h"
#include "core/point_cloud.h"
#include "core/point_filter.h"
#include "io/las_header.h"

namespace parallax::python {

// What the file said about itself beyond the points: the Python PointCloud's metadata.
struct CloudMetadata {
  std::string path;                     // the file read; empty for a cloud built from arrays
  std::string format;                   // the format table's id: "ply", "las", ...; empty: none
  std::string crs_wkt;                  // OGC WKT when the file states one; empty otherwise
  std::string crs_summary;              // "EPSG:26915 (GeoTIFF keys)", "none"
  std::optional<int> las_point_format;  // LAS and LAZ only
  std::string las_version;              // "1.4"; LAS and LAZ only
  std::vector<LasVlr> vlrs;             // LAS and LAZ: VLRs then EVLRs
};

struct CloudHandle {
  PointCloud cloud;
  CloudMetadata metadata;
  // x, y, z in world coordinates (double), computed on first use: positions are int32 with a
  // scale and offset (core/quantization.h), so world values cannot be a view of them.
  std::array<Column<double>, 3> world;
};

using CloudPtr = std::shared_ptr<CloudHandle>;

// Where a column's values live in the cloud and how numpy sees them.
struct ColumnView {
  void* data = nullptr;
  pybind11::dtype dtype;
  std::size_t stride = 0;  // bytes between points
  bool writeable = true;
};

// The names a cloud's columns go by, in the source's order (PointCloud::attributeOrder(): a PLY
// of x y z nx ny nz red green blue lists them so), which writers keep.
std::vector<std::string> columnNames(const PointCloud& cloud);

// The column `name` as the model holds it. `raw`: positions as their int32 values, colours as
// the 16-bit values a LAS source stored (when it stored them). x, y, z without `raw` are the world
// coordinates, computed into handle.world on first use (read only: a write there would not reach
// the positions). Throws KeyError naming the columns there are.
ColumnView columnView(CloudHandle& handle, const std::string& name, bool raw);

// A PointCloud built from a dict of numpy arrays (x, y, z required; the names of columnNames()
// for the model's own columns, anything else a scalar column of the array's type). Positions are
// quantized with `scale` and `offset` where given, else chooseQuantization of their bounds.
// Throws ValueError naming the column and what was expected.
PointCloud cloudFromArrays(const pybind11::dict& arrays,
                           const std::optional<std::array<double, 3>>& scale,
                           const std::optional<std::array<double, 3>>& offset);

// The filters the command line has (filter_options.h there), from Python values:
//   classes: iterable of ASPRS class numbers 0-255
//   returns: iterable of "first", "last", "intermediate", "single", "multiple" or numbers 1-15
//   intensity, elevation, gps_time: (min, max), inclusive
//   clip_box: (xmin, ymin, zmin, xmax, ymax, zmax[, yaw_degrees]) in world coordinates
//   clip_polygon: a sequence of (x, y) world coordinates, at least 3
//   clip_mode: "inside" (default) or "outside"
// Unset (None) arguments keep everything. Throws ValueError naming the argument and what was
// expected.
struct FilterArguments {
  pybind11::object classes = pybind11::none(), returns = pybind11::none();
  pybind11::object intensity = pybind11::none(), elevation = pybind11::none(),
                   gps_time = pybind11::none();
  pybind11::object clip_box = pybind11::none(), clip_polygon = pybind11::none();
  std::string clip_mode = "inside";
};
PointFilter pointFilterFrom(const FilterArguments& arguments);

void bindPointCloud(pybind11::module_& m);
void bindReadWrite(pybind11::module_& m);
void bindOctree(pybind11::module_& m);
void bindRender(pybind11::module_& m);
void bindCommands(pybind11::module_& m);

// (x, y, z) as a Python tuple: what bounds, scales and offsets are given as.
inline pybind11::tuple triple(const std::array<double, 3>& values) {
  return pybind11::make_tuple(values[0], values[1], values[2]);
}

}  // namespace parallax::python
