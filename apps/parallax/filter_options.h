// The point filter options of `parallax render`, `view` and `convert`: --classes, --clip-box,
// --clip-mode (core/point_filter.h). One parser, so that a list means the same everywhere.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"
#include "core/point_filter.h"

namespace parallax::cli {

struct FilterOptions {
  std::string classes;   // "2,6,9-12"; empty: every class
  std::string clip_box;  // "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX"; empty: no box
  std::string clip_mode = "inside";
};

// Registers --classes, --clip-box and --clip-mode; `what` ends their help texts ("drawn",
// "written").
void addFilterOptions(CLI::App& command, FilterOptions& options, const std::string& what);

// The classes of a list of ASPRS class numbers (0-255) and ranges, "2,6,9-12", in the order
// given (repeats kept). Throws std::invalid_argument that names --classes, the item and what was
// expected.
std::vector<int> parseClassList(std::string_view text);

// The box of "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX" (world coordinates, inclusive). Throws
// std::invalid_argument that names --clip-box, the item and what was expected; a minimum above
// its maximum is an error.
Bounds3 parseClipBox(std::string_view text);

// The filter of the options (keeps everything without them); throws as the parsers do, and for
// an unknown --clip-mode.
PointFilter pointFilterFrom(const FilterOptions& options);

}  // namespace parallax::cli
