#include "command_words.h"

#include <algorithm>

namespace py = pybind11;

namespace parallax::python {

std::string commandWord(const std::string& keyword, const py::handle& value) {
  if (py::isinstance<py::str>(value)) return py::cast<std::string>(value);
  if (py::isinstance<py::bool_>(value)) {
    throw py::type_error(keyword + ": True or False only for a switch, found inside a sequence");
  }
  if (py::hasattr(value, "__iter__")) {
    std::string text;
    for (const py::handle item : value) {
      if (!py::isinstance<py::str>(item) && py::hasattr(item, "__iter__")) {
        throw py::type_error(keyword + ": expected numbers or names, found a nested sequence");
      }
      text += (text.empty() ? "" : ",") + commandWord(keyword, item);
    }
    return text;
  }
  return std::string(py::str(value));  // a number (Python's or numpy's)
}

void appendOptionWords(const CLI::App& app, const py::kwargs& kwargs, const std::string& function,
                       std::vector<std::string>& words) {
  for (const auto& [key, value] : kwargs) {
    const std::string keyword = py::cast<std::string>(key);
    std::string name = "--" + keyword;
    std::replace(name.begin(), name.end(), '_', '-');
    if (!app.get_option_no_throw(name)) {
      throw py::type_error(function + "() got an unexpected keyword argument '" + keyword +
                           "' (the options of `parallax " + function + "`, with _ for -)");
    }
    if (value.is_none()) continue;  // the default
    if (py::isinstance<py::bool_>(value)) {
      if (value.cast<bool>()) words.push_back(name);
      continue;
    }
    words.push_back(name);
    words.push_back(commandWord(keyword, value));
  }
}

}  // namespace parallax::python
