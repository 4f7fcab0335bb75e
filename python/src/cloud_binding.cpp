// The Python `PointCloud`: columns as numpy arrays over the C++ columns, and the file's metadata.
#include <pybind11/stl.h>

#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

// A numpy array over the column, whose base is `self` (the Python PointCloud): the cloud lives as
// long as the array, and nothing is copied.
py::array arrayOf(const py::object& self, const std::string& name, bool raw) {
  CloudHandle& handle = self.cast<CloudHandle&>();
  const ColumnView view = columnView(handle, name, raw);
  const auto count = py::ssize_t(handle.cloud.count);
  if (count == 0) return py::array(view.dtype, std::vector<py::ssize_t>{0});
  py::array array(view.dtype, {count}, {py::ssize_t(view.stride)}, view.data, self);
  if (!view.writeable) array.attr("setflags")(py::arg("write") = false);
  return array;
}

std::string reprOf(const CloudHandle& handle) {
  std::string text = "<parallax.PointCloud " + std::to_string(handle.cloud.count) + " points";
  if (!handle.metadata.format.empty()) text += ", " + handle.metadata.format;
  if (!handle.metadata.path.empty()) text += " from '" + handle.metadata.path + "'";
  std::string names;
  for (const auto& name : columnNames(handle.cloud)) names += (names.empty() ? "" : " ") + name;
  return text + ": " + names + ">";
}

}  // namespace

void bindPointCloud(py::module_& m) {
  py::class_<LasVlr>(m, "Vlr",
                     "A LAS variable length record (or extended one) as the file holds it.")
      .def_readonly("user_id", &LasVlr::user_id)
      .def_readonly("record_id", &LasVlr::record_id)
      .def_readonly("description", &LasVlr::description)
      .def_readonly("extended", &LasVlr::extended, "True for an EVLR (after the points, LAS 1.4)")
      .def_property_readonly(
          "data",
          [](const LasVlr& vlr) {
            return py::bytes(reinterpret_cast<const char*>(vlr.data.data()), vlr.data.size());
          },
          "The payload: projection and spec records in full; empty for records Parallax does "
          "not read (waveform data can be gigabytes)")
      .def_readonly("data_size", &LasVlr::data_size)
      .def("__repr__", [](const LasVlr& vlr) {
        return "<parallax.Vlr " + vlr.user_id + " " + std::to_string(vlr.record_id) + " (" +
               std::to_string(vlr.data_size) + " bytes)>";
      });

  py::class_<CloudHandle, CloudPtr>(m, "PointCloud", R"doc(
Points as columns: numpy arrays over Parallax's own columns, without a copy.

``pc["x"]`` (and y, z) are world coordinates as float64 (computed once from the int32 positions
and kept; read only). ``pc.raw("x")`` is the int32 column itself, with ``pc.scale`` and
``pc.offset``: world = raw * scale + offset. Every other column (``red``, ``nx``, ``intensity``,
``classification``, ``gps_time``, ...) is a writable view: a write through it changes the cloud
that ``parallax.write`` writes. The arrays' ``base`` is this object, which keeps the columns alive.
)doc")
      .def("__len__", [](const CloudHandle& handle) { return handle.cloud.count; })
      .def_property_readonly("count", [](const CloudHandle& handle) { return handle.cloud.count; })
      .def_property_readonly(
          "columns", [](const CloudHandle& handle) { return columnNames(handle.cloud); },
          "The columns' names, in the file's order (the order writers keep)")
      .def("keys", [](const CloudHandle& handle) { return columnNames(handle.cloud); })
      .def("__contains__",
           [](const CloudHandle& handle, const std::string& name) {
             const auto names = columnNames(handle.cloud);
             return std::find(names.begin(), names.end(), name) != names.end();
           })
      .def(
          "__getitem__",
          [](const py::object& self, const std::string& name) {
            return arrayOf(self, name, false);
          },
          py::arg("name"), "The column `name` as a numpy array (x, y, z: world float64)")
      .def(
          "__setitem__",
          [](const py::object& self, const std::string& name, const py::object& value) {
            const py::array column = arrayOf(self, name, false);  // KeyError: no such column
            // `pc[name] *= 0.5` changes the view in place, then hands it back here: done.
            if (py::isinstance<py::array>(value)) {
              const auto array = value.cast<py::array>();
              if (array.data() == column.data() && array.ndim() == 1 &&
                  array.shape(0) == column.shape(0) && array.strides(0) == column.strides(0)) {
                return;
              }
            }
            if (!column.writeable()) {
              throw py::value_error(
                  "column '" + name +
                  "' is read only: world x, y and z are computed from the int32 positions; "
                  "write pc.raw(\"" +
                  name + "\") (world = raw * scale + offset)");
            }
            column.attr("__setitem__")(py::ellipsis(), value);  // numpy's broadcasting and casts
          },
          py::arg("name"), py::arg("value"),
          "Writes `value` (an array of len(pc) values, or one value) into the column `name`; "
          "`pc[name] *= 2` and the like work in place. x, y, z are read only (write raw(\"x\"))")
      .def(
          "raw",
          [](const py::object& self, const std::string& name) { return arrayOf(self, name, true); },
          py::arg("name"),
          "The column as stored: x, y, z as their int32 values (world = raw * scale + offset); "
          "red, green, blue as the 16-bit values a LAS file stored; others as __getitem__")
      .def(
          "to_dict",
          [](const py::object& self) {
            py::dict columns;
            for (const auto& name : columnNames(self.cast<CloudHandle&>().cloud)) {
              columns[py::str(name)] = arrayOf(self, name, false);
            }
            return columns;
          },
          "Every column by name (views, as __getitem__ gives them)")
      .def_property_readonly(
          "scale",
          [](const CloudHandle& handle) { return triple(handle.cloud.quantization.scale); })
      .def_property_readonly(
          "offset",
          [](const CloudHandle& handle) { return triple(handle.cloud.quantization.offset); })
      .def_property_readonly(
          "bounds",
          [](const CloudHandle& handle) {
            return py::make_tuple(triple(handle.cloud.bounds.min), triple(handle.cloud.bounds.max));
          },
          "((xmin, ymin, zmin), (xmax, ymax, zmax)) of the points held, world coordinates")
      .def_property_readonly("path",
                             [](const CloudHandle& handle) -> py::object {
                               if (handle.metadata.path.empty()) return py::none();
                               return py::str(handle.metadata.path);
                             })
      .def_property_readonly("format",
                             [](const CloudHandle& handle) -> py::object {
                               if (handle.metadata.format.empty()) return py::none();
                               return py::str(handle.metadata.format);
                             })
      .def_property_readonly(
          "crs_wkt",
          [](const CloudHandle& handle) -> py::object {
            if (handle.metadata.crs_wkt.empty()) return py::none();
            return py::str(handle.metadata.crs_wkt);
          },
          "The coordinate reference system as OGC WKT, when the file states it so; else None")
      .def_property_readonly(
          "crs", [](const CloudHandle& handle) { return handle.metadata.crs_summary; },
          "One line: 'EPSG:26915 (GeoTIFF keys)', the WKT's name, or 'none'")
      .def_property_readonly("point_format",
                             [](const CloudHandle& handle) -> py::object {
                               if (!handle.metadata.las_point_format) return py::none();
                               return py::int_(*handle.metadata.las_point_format);
                             })
      .def_property_readonly("las_version",
                             [](const CloudHandle& handle) -> py::object {
                               if (handle.metadata.las_version.empty()) return py::none();
                               return py::str(handle.metadata.las_version);
                             })
      .def_property_readonly(
          "vlrs", [](const CloudHandle& handle) { return handle.metadata.vlrs; },
          "LAS and LAZ: the VLRs then the EVLRs, as Vlr objects; empty for other formats")
      .def("__repr__", [](const CloudHandle& handle) { return reprOf(handle); });
}

}  // namespace parallax::python
