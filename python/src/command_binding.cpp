// parallax.convert and parallax.process: the commands themselves (apps/parallax/
// command_convert.cpp, command_process.cpp), run in this process with the GIL released, their
// options from keyword arguments (command_words.h), their output the command line's byte for
// byte. Progress goes to a Python callable through the commands' stage observer
// (progress_observer.h); errors in the input are parallax.InputError with the command's message.
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "command_words.h"
#include "commands.h"
#include "progress_observer.h"
#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

// One command at a time: the stage observer is the process's.
std::mutex command_mutex;

// Inputs: one path, or a sequence of them (convert and process read several as one cloud).
std::vector<std::string> inputWords(const py::object& inputs) {
  const py::module_ os = py::module_::import("os");
  if (py::isinstance<py::str>(inputs) || py::hasattr(inputs, "__fspath__")) {
    return {py::str(os.attr("fspath")(inputs))};
  }
  std::vector<std::string> words;
  for (const py::handle input : inputs) words.push_back(py::str(os.attr("fspath")(input)));
  if (words.empty()) throw py::value_error("src: expected at least one input");
  return words;
}

// Calls the Python callable from the command's threads, with the GIL, one call at a time; what
// it raises is kept and raised once the command has ended (a command cannot be interrupted).
class ProgressForward {
 public:
  explicit ProgressForward(py::object callback) : callback_(std::move(callback)) {}
  void operator()(const std::string& stage, std::uint64_t done, std::uint64_t total) {
    const std::lock_guard lock(mutex_);
    if (error_) return;
    py::gil_scoped_acquire gil;
    try {
      callback_(done, total ? py::object(py::int_(total)) : py::object(py::none()),
                py::arg("stage") = stage);
    } catch (py::error_already_set& error) {
      error_ = std::make_unique<py::error_already_set>(std::move(error));
    }
  }
  void raiseIfFailed() {
    if (error_) throw std::move(*error_);
  }

 private:
  py::object callback_;
  std::mutex mutex_;
  std::unique_ptr<py::error_already_set> error_;
};

// Parses `words` (the command's name first) with the command's own registration and runs it.
void runCommand(const std::string& name, std::vector<std::string> words,
                const py::object& progress) {
  CLI::App app("parallax");
  app.require_subcommand(1);
  const cli::Command command =
      name == "convert" ? cli::addConvertCommand(app) : cli::addProcessCommand(app);
  std::reverse(words.begin(), words.end());  // CLI11 takes a vector last word first
  try {
    app.parse(words);
  } catch (const CLI::ParseError& error) {
    throw py::value_error(name + ": " + error.what());
  }
  std::shared_ptr<ProgressForward> forward;
  if (!progress.is_none()) forward = std::make_shared<ProgressForward>(progress);
  int status = 0;
  {
    py::gil_scoped_release release;
    const std::lock_guard lock(command_mutex);
    if (forward) {
      cli::setProgressObserver([forward](const std::string& stage, std::uint64_t done,
                                         std::uint64_t total) { (*forward)(stage, done, total); });
    }
    struct ClearObserver {
      ~ClearObserver() { cli::setProgressObserver({}); }
    } clear;
    status = command.run();
  }
  if (forward) forward->raiseIfFailed();
  if (status != 0) {
    throw std::runtime_error("parallax " + name + " ended with status " + std::to_string(status));
  }
}

// The words of `name SRC... -o DST -q`, then `extra`, then the keyword arguments.
std::vector<std::string> commandWords(const std::string& name, const py::object& src,
                                      const py::object& dst, const py::kwargs& kwargs,
                                      const std::vector<std::string>& extra) {
  CLI::App app("parallax");
  const cli::Command command =
      name == "convert" ? cli::addConvertCommand(app) : cli::addProcessCommand(app);
  std::vector<std::string> words{name};
  for (std::string& input : inputWords(src)) words.push_back(std::move(input));
  words.push_back("-o");
  words.push_back(py::str(py::module_::import("os").attr("fspath")(dst)));
  words.push_back("-q");  // the report on stderr is the command line's; progress comes by callback
  words.insert(words.end(), extra.begin(), extra.end());
  appendOptionWords(*command.subcommand, kwargs, name, words);
  return words;
}

void convert(const py::object& src, const py::object& dst, const py::object& progress,
             const py::kwargs& kwargs) {
  runCommand("convert", commandWords("convert", src, dst, kwargs, {}), progress);
}

// steps: (name, value) pairs in the order they run (value True for a switch such as
// "curvature"), or a dict in its order.
void process(const py::object& src, const py::object& dst, const py::object& steps,
             const py::object& progress, const py::kwargs& kwargs) {
  std::vector<std::string> extra;
  const py::object pairs = py::isinstance<py::dict>(steps) ? steps.attr("items")() : steps;
  for (const py::handle pair : pairs) {
    const py::tuple step = py::reinterpret_borrow<py::object>(pair).cast<py::tuple>();
    if (step.size() != 2) {
      throw py::value_error("steps: expected (name, value) pairs such as (\"normals\", 16)");
    }
    std::string option = "--" + py::cast<std::string>(step[0]);
    std::replace(option.begin(), option.end(), '_', '-');
    if (py::isinstance<py::bool_>(step[1])) {
      if (step[1].cast<bool>()) extra.push_back(option);
      continue;
    }
    extra.push_back(option);
    extra.push_back(commandWord(py::cast<std::string>(step[0]), step[1]));
  }
  runCommand("process", commandWords("process", src, dst, kwargs, extra), progress);
}

}  // namespace

void bindCommands(py::module_& m) {
  m.def("convert", &convert, py::arg("src"), py::arg("dst"), py::kw_only(),
        py::arg("progress") = py::none(),
        R"doc(`parallax convert SRC... -o DST` in this process: the same output, byte for byte.

src: a path or URL, or a sequence of them (read as one cloud). dst: a point file (its extension
picks the format), a .copc.laz file, or a Potree 2.0 directory (format="potree", or a name
ending in "/"). Keyword arguments are the command's options with _ for -: sampling=,
classes=, clip_box=, las_version=, point_format=, memory=, ... (True for a switch).
progress: callable(done, total, stage=NAME) for each stage of an octree build, in points; a
file to a file reports stage="reading" (in points, or "reading bytes" for text) and "writing".
Raises parallax.InputError for a bad input, ValueError for a refused option.)doc");
  m.def("process", &process, py::arg("src"), py::arg("dst"), py::kw_only(),
        py::arg("steps") = py::list(), py::arg("progress") = py::none(),
        R"doc(`parallax process SRC... -o DST STEP...` in this process: the same output.

steps: the steps in the order they run, as (name, value) pairs or a dict:
[("normals", 16), ("outliers", "statistical:8,2"), ("subsample", "voxel:0.05")]; True for a
switch (("curvature", True)). Other keyword arguments are the command's options (memory=,
orient=, columns=, ascii=, ...). progress: callable(done, total, stage=NAME) per step and pass.
Raises parallax.InputError for a bad input, ValueError for a refused option.)doc");
}

}  // namespace parallax::python
