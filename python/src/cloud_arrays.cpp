// Columns of a PointCloud as numpy sees them, and clouds built from numpy arrays.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>

#include "core/color_depth.h"
#include "core/quantization.h"
#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

py::dtype dtypeOf(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return py::dtype::of<std::int8_t>();
    case ScalarType::UInt8:
      return py::dtype::of<std::uint8_t>();
    case ScalarType::Int16:
      return py::dtype::of<std::int16_t>();
    case ScalarType::UInt16:
      return py::dtype::of<std::uint16_t>();
    case ScalarType::Int32:
      return py::dtype::of<std::int32_t>();
    case ScalarType::UInt32:
      return py::dtype::of<std::uint32_t>();
    case ScalarType::Float32:
      return py::dtype::of<float>();
    case ScalarType::Float64:
      return py::dtype::of<double>();
  }
  throw std::logic_error("dtypeOf: unknown ScalarType");
}

// The scalar type of a numpy dtype; nullopt for anything the model has no type for.
std::optional<ScalarType> scalarTypeOf(const py::dtype& dtype) {
  const char kind = dtype.kind();
  const auto size = dtype.itemsize();
  if (kind == 'i') {
    if (size == 1) return ScalarType::Int8;
    if (size == 2) return ScalarType::Int16;
    if (size == 4) return ScalarType::Int32;
  } else if (kind == 'u' || kind == 'b') {
    if (size == 1) return ScalarType::UInt8;
    if (size == 2) return ScalarType::UInt16;
    if (size == 4) return ScalarType::UInt32;
  } else if (kind == 'f') {
    if (size == 4) return ScalarType::Float32;
    if (size == 8) return ScalarType::Float64;
  }
  return std::nullopt;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// Calls f.template operator()<T>() with the C++ type of `type`.
template <class F>
void withScalarType(ScalarType type, F&& f) {
  switch (type) {
    case ScalarType::Int8:
      return f.template operator()<std::int8_t>();
    case ScalarType::UInt8:
      return f.template operator()<std::uint8_t>();
    case ScalarType::Int16:
      return f.template operator()<std::int16_t>();
    case ScalarType::UInt16:
      return f.template operator()<std::uint16_t>();
    case ScalarType::Int32:
      return f.template operator()<std::int32_t>();
    case ScalarType::UInt32:
      return f.template operator()<std::uint32_t>();
    case ScalarType::Float32:
      return f.template operator()<float>();
    case ScalarType::Float64:
      return f.template operator()<double>();
  }
}

int axisOf(const std::string& name) {
  return name == "x" ? 0 : name == "y" ? 1 : 2;
}

void computeWorld(CloudHandle& handle, int axis) {
  const PointCloud& cloud = handle.cloud;
  Column<double> world(cloud.count);
  const double scale = cloud.quantization.scale[axis];
  const double offset = cloud.quantization.offset[axis];
  const std::int32_t* q = &cloud.positions.data()->x + axis;
  double* out = world.data();
  {
    // Without the GIL while computing: the loop touches no Python object. It is taken again
    // before the column is stored; a thread that computed it meanwhile stored it first, and
    // arrays may view that one already: it is kept.
    py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cloud.count, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i < range.end(); ++i) {
                          out[i] = double(q[3 * i]) * scale + offset;
                        }
                      });
  }
  if (handle.world[std::size_t(axis)].size() != cloud.count) {
    handle.world[std::size_t(axis)] = std::move(world);
  }
}

}  // namespace

std::vector<std::string> columnNames(const PointCloud& cloud) {
  return cloud.attributeOrder();
}

ColumnView columnView(CloudHandle& handle, const std::string& name, bool raw) {
  PointCloud& cloud = handle.cloud;
  if (name == "x" || name == "y" || name == "z") {
    const int axis = axisOf(name);
    if (raw) {
      return {&cloud.positions.data()->x + axis, py::dtype::of<std::int32_t>(), sizeof(Int3)};
    }
    if (handle.world[std::size_t(axis)].size() != cloud.count) computeWorld(handle, axis);
    return {handle.world[std::size_t(axis)].data(), py::dtype::of<double>(), sizeof(double), false};
  }
  const bool colour = name == "red" || name == "green" || name == "blue" ||
                      (name == "alpha" && cloud.source.has_alpha);
  if (colour && cloud.hasColors()) {
    const std::size_t channel = name == "red" ? 0 : name == "green" ? 1 : name == "blue" ? 2 : 3;
    if (raw && cloud.hasStoredColors() && channel < 3) {
      return {&cloud.stored_colors.data()->r + channel, py::dtype::of<std::uint16_t>(),
              sizeof(Rgb16)};
    }
    return {&cloud.colors.data()->r + channel, py::dtype::of<std::uint8_t>(), sizeof(Rgba8)};
  }
  if ((name == "nx" || name == "ny" || name == "nz") && cloud.hasNormals()) {
    const std::size_t axis = std::size_t(name[1] - 'x');
    return {&cloud.normals.data()->x + axis, py::dtype::of<float>(), sizeof(Float3)};
  }
  if (name == "intensity" && cloud.hasIntensity()) {
    return {cloud.intensity.data(), py::dtype::of<float>(), sizeof(float)};
  }
  if (name == "classification" && cloud.hasClassification()) {
    return {cloud.classification.data(), py::dtype::of<std::uint8_t>(), 1};
  }
  for (ScalarColumn& column : cloud.scalars) {
    if (column.name == name) {
      return {column.data.data(), dtypeOf(column.type), scalarSize(column.type)};
    }
  }
  throw py::key_error("no column '" + name +
                      "' in this cloud; its columns: " + joined(columnNames(cloud)));
}

namespace {

// `array` as a contiguous 1-D array of `count` values of type T (numpy converts; a wrong length
// or a value numpy cannot convert is a ValueError naming the column).
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> columnOf(const py::handle& array,
                                                                   const std::string& name,
                                                                   std::size_t count) {
  py::array_t<T, py::array::c_style | py::array::forcecast> values;
  try {
    values = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(array);
  } catch (const py::error_already_set&) {
    values = {};
  }
  if (!values || values.ndim() != 1 || std::size_t(values.shape(0)) != count) {
    throw py::value_error("column '" + name + "': expected a 1-D array of " +
                          std::to_string(count) + " numbers (as many as 'x' has), found " +
                          std::string(py::str(py::repr(array))).substr(0, 80));
  }
  return values;
}

}  // namespace

PointCloud cloudFromArrays(const py::dict& arrays,
                           const std::optional<std::array<double, 3>>& scale,
                           const std::optional<std::array<double, 3>>& offset) {
  for (const char* axis : {"x", "y", "z"}) {
    if (!arrays.contains(axis)) {
      throw py::value_error(std::string("the arrays have no '") + axis +
                            "' column: x, y and z (world coordinates) are required");
    }
  }
  const py::array x_any = py::array::ensure(arrays["x"]);
  if (!x_any || x_any.ndim() != 1) {
    throw py::value_error("column 'x': expected a 1-D array of world coordinates");
  }
  PointCloud cloud;
  cloud.count = std::uint64_t(x_any.shape(0));
  const std::size_t count = cloud.count;
  const auto x = columnOf<double>(arrays["x"], "x", count);
  const auto y = columnOf<double>(arrays["y"], "y", count);
  const auto z = columnOf<double>(arrays["z"], "z", count);
  const std::array<const double*, 3> xyz = {x.data(), y.data(), z.data()};
  cloud.source.position = x_any.dtype().kind() == 'f' && x_any.itemsize() == 4
                              ? ScalarType::Float32
                              : ScalarType::Float64;

  Bounds3 bounds;
  for (std::size_t i = 0; i < count; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(xyz[std::size_t(axis)][i])) {
        throw py::value_error("column '" + std::string(1, char('x' + axis)) + "', point " +
                              std::to_string(i) + ": expected a finite coordinate, found " +
                              std::to_string(xyz[std::size_t(axis)][i]));
      }
    }
    bounds.extend(x.data()[i], y.data()[i], z.data()[i]);
  }
  cloud.quantization = chooseQuantization(bounds);
  if (scale) cloud.quantization.scale = *scale;
  if (offset) cloud.quantization.offset = *offset;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(cloud.quantization.scale[std::size_t(axis)] > 0.0)) {
      throw py::value_error("scale: expected three positive numbers");
    }
  }
  cloud.positions = Column<Int3>(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::array<std::int32_t, 3> q{};
    for (int axis = 0; axis < 3; ++axis) {
      const double world = xyz[std::size_t(axis)][i];
      if (!cloud.quantization.fits(axis, world)) {
        throw py::value_error("column '" + std::string(1, char('x' + axis)) + "', point " +
                              std::to_string(i) + ": " + std::to_string(world) +
                              " does not fit the int32 grid of the scale and offset given");
      }
      q[std::size_t(axis)] = cloud.quantization.toQuantized(axis, world);
    }
    cloud.positions[i] = {q[0], q[1], q[2]};
  }

  std::set<std::string> used = {"x", "y", "z"};
  if (arrays.contains("red") || arrays.contains("green") || arrays.contains("blue")) {
    for (const char* channel : {"red", "green", "blue"}) {
      if (!arrays.contains(channel)) {
        throw py::value_error(std::string("colour needs red, green and blue; '") + channel +
                              "' is missing");
      }
    }
    const bool sixteen = py::array::ensure(arrays["red"]).itemsize() == 2;
    const bool alpha = arrays.contains("alpha");
    cloud.colors = Column<Rgba8>(count);
    cloud.source.has_alpha = alpha;
    cloud.source.color = sixteen ? ScalarType::UInt16 : ScalarType::UInt8;
    if (sixteen) {
      // 16-bit values are kept as given for LAS and LAZ (stored_colors); their display form
      // is the nearest of value / 257, as las_reader.h reads a 16-bit file.
      cloud.stored_colors = Column<Rgb16>(count);
      const auto r = columnOf<std::uint16_t>(arrays["red"], "red", count);
      const auto g = columnOf<std::uint16_t>(arrays["green"], "green", count);
      const auto b = columnOf<std::uint16_t>(arrays["blue"], "blue", count);
      for (std::size_t i = 0; i < count; ++i) {
        const Rgb16 c{r.data()[i], g.data()[i], b.data()[i]};
        cloud.stored_colors[i] = c;
        cloud.colors[i] = {colorTo8Bits(c.r), colorTo8Bits(c.g), colorTo8Bits(c.b), 255};
      }
    } else {
      const auto r = columnOf<std::uint8_t>(arrays["red"], "red", count);
      const auto g = columnOf<std::uint8_t>(arrays["green"], "green", count);
      const auto b = columnOf<std::uint8_t>(arrays["blue"], "blue", count);
      for (std::size_t i = 0; i < count; ++i) {
        cloud.colors[i] = {r.data()[i], g.data()[i], b.data()[i], 255};
      }
    }
    if (alpha) {
      const auto a = columnOf<std::uint8_t>(arrays["alpha"], "alpha", count);
      for (std::size_t i = 0; i < count; ++i) cloud.colors[i].a = a.data()[i];
    }
    used.insert({"red", "green", "blue", "alpha"});
  }
  if (arrays.contains("nx") || arrays.contains("ny") || arrays.contains("nz")) {
    const auto nx = columnOf<float>(arrays["nx"], "nx", count);
    const auto ny = columnOf<float>(arrays["ny"], "ny", count);
    const auto nz = columnOf<float>(arrays["nz"], "nz", count);
    cloud.normals = Column<Float3>(count);
    for (std::size_t i = 0; i < count; ++i) {
      cloud.normals[i] = {nx.data()[i], ny.data()[i], nz.data()[i]};
    }
    used.insert({"nx", "ny", "nz"});
  }
  if (arrays.contains("intensity")) {
    const auto type = scalarTypeOf(py::array::ensure(arrays["intensity"]).dtype());
    cloud.source.intensity = type.value_or(ScalarType::Float32);
    const auto values = columnOf<float>(arrays["intensity"], "intensity", count);
    cloud.intensity = Column<float>(count);
    std::memcpy(cloud.intensity.data(), values.data(), count * sizeof(float));
    used.insert("intensity");
  }
  if (arrays.contains("classification")) {
    const auto values = columnOf<std::uint8_t>(arrays["classification"], "classification", count);
    cloud.classification = Column<std::uint8_t>(count);
    std::memcpy(cloud.classification.data(), values.data(), count);
    used.insert("classification");
  }
  for (const auto& [key, value] : arrays) {
    const std::string name = py::str(key);
    if (used.count(name) != 0) continue;
    const py::array any = py::array::ensure(value);
    const auto type = any ? scalarTypeOf(any.dtype()) : std::nullopt;
    if (!type) {
      throw py::value_error("column '" + name +
                            "': expected a numpy array of int8-32, uint8-32, float32 or float64");
    }
    ScalarColumn column{name, *type, ByteBuffer(count * scalarSize(*type))};
    // A named copy for the lambda: clang before 16 cannot capture a structured binding.
    const py::handle column_array = value;
    withScalarType(*type, [&]<class T>() {
      const auto values = columnOf<T>(column_array, name, count);
      std::memcpy(column.data.data(), values.data(), count * sizeof(T));
    });
    cloud.scalars.push_back(std::move(column));
  }
  // The dict's order is the order writers that choose one (PLY, text) put the columns in.
  for (const auto& [key, value] : arrays) cloud.source.order.push_back(py::str(key));
  cloud.computeBounds();
  return cloud;
}

}  // namespace parallax::python
