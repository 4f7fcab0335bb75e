// The Python module `parallax._parallax`: the compiled half of the package python/parallax.
#include "core/error.h"
#include "net/network.h"
#include "python_module.h"

namespace py = pybind11;

PYBIND11_MODULE(_parallax, m) {
  m.doc() = "Parallax: point clouds as numpy arrays (read, write, filter, octrees, render)";
  // Bad input is a parallax.InputError, a ValueError, with the C++ message (file, offset, field,
  // what was expected and found).
  py::register_exception<parallax::InputError>(m, "InputError", PyExc_ValueError);
  parallax::python::bindPointCloud(m);
  parallax::python::bindReadWrite(m);
  parallax::python::bindOctree(m);
  parallax::python::bindRender(m);
  parallax::python::bindCommands(m);
  // http(s) URLs through net's client and range cache (a program linking net does this before
  // main; an extension module is loaded later, and its static initialisers may be dropped).
  parallax::installHttpOpener();
}
