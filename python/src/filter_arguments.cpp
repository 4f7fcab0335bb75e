// The command line's point filters from Python values (python_module.h).
#include <cmath>
#include <stdexcept>

#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

std::vector<double> numbersOf(const py::object& value, const char* argument) {
  std::vector<double> numbers;
  try {
    for (const py::handle item : value) numbers.push_back(py::cast<double>(item));
  } catch (const py::cast_error&) {
    throw py::value_error(std::string(argument) + ": expected a sequence of numbers, found " +
                          std::string(py::str(py::repr(value))));
  } catch (const py::error_already_set&) {
    throw py::value_error(std::string(argument) + ": expected a sequence of numbers, found " +
                          std::string(py::str(py::repr(value))));
  }
  for (const double number : numbers) {
    if (!std::isfinite(number)) {
      throw py::value_error(std::string(argument) + ": expected finite numbers, found " +
                            std::string(py::str(py::repr(value))));
    }
  }
  return numbers;
}

std::optional<ValueRange> rangeOf(const py::object& value, const char* argument) {
  if (value.is_none()) return std::nullopt;
  const std::vector<double> bounds = numbersOf(value, argument);
  if (bounds.size() != 2 || bounds[0] > bounds[1]) {
    throw py::value_error(std::string(argument) + ": expected (min, max) with min <= max, found " +
                          std::string(py::str(py::repr(value))));
  }
  return ValueRange{bounds[0], bounds[1]};
}

ReturnKind returnKindOf(const std::string& name) {
  if (name == "first") return ReturnKind::First;
  if (name == "last") return ReturnKind::Last;
  if (name == "intermediate") return ReturnKind::Intermediate;
  if (name == "single") return ReturnKind::Single;
  if (name == "multiple") return ReturnKind::Multiple;
  throw py::value_error("returns: unknown kind '" + name +
                        "'; expected first, last, intermediate, single, multiple or a return "
                        "number 1-15");
}

}  // namespace

PointFilter pointFilterFrom(const FilterArguments& arguments) {
  PointFilter filter;
  if (!arguments.classes.is_none()) {
    std::vector<int> classes;
    for (const double value : numbersOf(arguments.classes, "classes")) {
      if (value < 0 || value > 255 || value != std::floor(value)) {
        throw py::value_error("classes: expected class numbers 0-255, found " +
                              std::to_string(value));
      }
      classes.push_back(int(value));
    }
    filter.keepOnlyClasses(classes);
  }
  if (!arguments.returns.is_none()) {
    std::vector<ReturnKind> kinds;
    std::vector<int> numbers;
    for (const py::handle item : arguments.returns) {
      if (py::isinstance<py::str>(item)) {
        kinds.push_back(returnKindOf(py::cast<std::string>(item)));
      } else if (py::isinstance<py::int_>(item)) {
        const int number = py::cast<int>(item);
        if (number < 1 || number > 15) {
          throw py::value_error("returns: expected return numbers 1-15, found " +
                                std::to_string(number));
        }
        numbers.push_back(number);
      } else {
        throw py::value_error("returns: expected kinds (\"first\", ...) or return numbers, found " +
                              std::string(py::str(py::repr(item))));
      }
    }
    filter.keepOnlyReturns(kinds, numbers);
  }
  filter.intensity = rangeOf(arguments.intensity, "intensity");
  filter.elevation = rangeOf(arguments.elevation, "elevation");
  filter.gps_time = rangeOf(arguments.gps_time, "gps_time");
  if (arguments.clip_mode != "inside" && arguments.clip_mode != "outside") {
    throw py::value_error("clip_mode: expected \"inside\" or \"outside\", found '" +
                          arguments.clip_mode + "'");
  }
  const bool outside = arguments.clip_mode == "outside";
  if (!arguments.clip_box.is_none()) {
    const std::vector<double> box = numbersOf(arguments.clip_box, "clip_box");
    if (box.size() != 6 && box.size() != 7) {
      throw py::value_error(
          "clip_box: expected (xmin, ymin, zmin, xmax, ymax, zmax[, yaw]), found " +
          std::to_string(box.size()) + " numbers");
    }
    if (box[0] > box[3] || box[1] > box[4] || box[2] > box[5]) {
      throw py::value_error("clip_box: a minimum is above its maximum");
    }
    Bounds3 bounds;
    bounds.extend(box[0], box[1], box[2]);
    bounds.extend(box[3], box[4], box[5]);
    filter.setClipBox(bounds, outside, box.size() == 7 ? box[6] : 0.0);
  }
  if (!arguments.clip_polygon.is_none()) {
    for (const py::handle vertex : arguments.clip_polygon) {
      const std::vector<double> xy =
          numbersOf(py::reinterpret_borrow<py::object>(vertex), "clip_polygon");
      if (xy.size() != 2) {
        throw py::value_error("clip_polygon: expected (x, y) vertices, found one of " +
                              std::to_string(xy.size()) + " numbers");
      }
      filter.polygon.push_back({xy[0], xy[1]});
    }
    if (filter.polygon.size() < 3) {
      throw py::value_error("clip_polygon: expected at least 3 vertices, found " +
                            std::to_string(filter.polygon.size()));
    }
    filter.clip_outside = outside;
  }
  return filter;
}

}  // namespace parallax::python
