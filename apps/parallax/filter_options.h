// The point filter options of `parallax render`, `view`, `pick` and `convert`: --classes,
// --returns, --intensity, --elevation, --gps-time, --clip-box, --clip-polygon, --clip-mode
// (core/point_filter.h). One parser, so that a list means the same everywhere.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"
#include "core/point_filter.h"

namespace parallax::cli {

struct FilterOptions {
  std::string classes;    // "2,6,9-12"; empty: every class
  std::string returns;    // "first,last", "1,2", "single"; empty: every return
  std::string intensity;  // "MIN,MAX"; empty: no bound (also elevation, gps_time)
  std::string elevation;  // world z
  std::string gps_time;
  std::string clip_box;      // "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX[,YAW]"; empty: no box
  std::string clip_polygon;  // a polygon file (io/polygon_reader.h); empty: none
  std::string clip_mode;     // inside (empty) or outside
};

// Registers the options above; `what` ends their help texts ("drawn",
// "written").
void addFilterOptions(CLI::App& command, FilterOptions& options, const std::string& what);

// The classes of a list of ASPRS class numbers (0-255) and ranges, "2,6,9-12", in the order
// given (repeats kept). Throws std::invalid_argument that names --classes, the item and what was
// expected.
std::vector<int> parseClassList(std::string_view text);

// The box of "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX[,YAW]" (world coordinates, inclusive; YAW in degrees,
// PointFilter::setClipBox's turn). Throws std::invalid_argument that names --clip-box, the item
// and what was expected; a minimum above its maximum is an error.
ClipBox parseClipBox(std::string_view text);

// The kinds and explicit return numbers of "first,last,2": keywords first, last, intermediate,
// single, multiple and numbers 1-15 (ranges N-M too). Throws std::invalid_argument naming
// --returns, the item and what was expected.
struct ReturnSelection {
  std::vector<ReturnKind> kinds;
  std::vector<int> numbers;
};
ReturnSelection parseReturnList(std::string_view text);

// The range "MIN,MAX" of the option `name` (inclusive; MIN <= MAX, finite numbers). Throws
// std::invalid_argument naming the option, the item and what was expected.
ValueRange parseRange(std::string_view name, std::string_view text);

// Where a filter is applied: the shaders take at most PointFilter::kMaxGpuPolygonVertices
// polygon vertices; the converter's CPU test has no limit.
enum class FilterTarget { Gpu, Cpu };

// The filter of the options (keeps everything without them); throws as the parsers do, for an
// unknown --clip-mode or one without a region, and for a polygon beyond the target's limit. The
// polygon file's errors are InputError (io/polygon_reader.h).
PointFilter pointFilterFrom(const FilterOptions& options, FilterTarget target);

}  // namespace parallax::cli
