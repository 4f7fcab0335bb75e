// Python arguments as the words of a `parallax` command line, for the functions that run a
// command's own code (render, pick, convert, process): size_mode="adaptive" is --size-mode
// adaptive, eye=(1, 2, 3) is --eye 1,2,3, edl=True is --edl, None and False leave the default.
#pragma once

#include <pybind11/pybind11.h>

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace parallax::python {

// One value as one word: strings as they are, numbers as Python prints them, sequences joined by
// commas. Throws TypeError naming `keyword` for a nested sequence or a bool inside one.
std::string commandWord(const std::string& keyword, const pybind11::handle& value);

// Appends the words of `kwargs` to `words`, each keyword an option of `app` with _ for -.
// Throws TypeError naming `function` and the keyword for one `app` does not have.
void appendOptionWords(const CLI::App& app, const pybind11::kwargs& kwargs,
                       const std::string& function, std::vector<std::string>& words);

}  // namespace parallax::python
