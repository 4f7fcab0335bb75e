// `parallax raster IN -o OUT.tif --resolution R --value V`: an elevation, intensity or density
// raster of a cloud as a float32 GeoTIFF, streamed out of core (raster/raster_builder.h).
#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_options.h"
#include "progress_options.h"
#include "raster/raster_builder.h"

namespace parallax::cli {

namespace {

struct RasterArgs {
  std::string input;
  std::string output;
  double resolution = 0.0;
  std::string value = "min";
  std::string bounds;
  double idw_radius = 0.0;
  bool fill = false;
  double fill_radius = 0.0;
  std::string minus;
  bool hillshade = false;
  std::uint64_t memory_mb = 2048;
  std::vector<std::string> columns;
  FilterOptions filter_options;
  bool quiet = false;
};

// "XMIN,YMIN,XMAX,YMAX".
std::array<double, 4> parseBounds(const std::string& text) {
  std::array<double, 4> bounds{};
  std::size_t start = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t end = i < 3 ? text.find(',', start) : text.size();
    if (end == std::string::npos) {
      throw std::invalid_argument("--bounds: expected XMIN,YMIN,XMAX,YMAX (four numbers), found '" +
                                  text + "'");
    }
    const std::string item = text.substr(start, end - start);
    std::size_t used = 0;
    try {
      bounds[i] = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) {
      throw std::invalid_argument("--bounds: item " + std::to_string(i + 1) +
                                  " is not a number: '" + item + "'");
    }
    start = end + 1;
  }
  return bounds;
}

int runRasterCommand(RasterArgs args) {
  RasterOptions options;
  options.input.path = args.input;
  options.input.text_columns = args.columns;
  if (args.filter_options.returns == "all") args.filter_options.returns.clear();
  options.input.filter = pointFilterFrom(args.filter_options, FilterTarget::Cpu);
  options.output = args.output;
  options.resolution = args.resolution;
  const auto value = rasterValueNamed(args.value);
  if (!value) {
    throw std::invalid_argument("--value: expected one of " + rasterValueNames() + ", found '" +
                                args.value + "'");
  }
  options.value = *value;
  if (!args.bounds.empty()) options.bounds = parseBounds(args.bounds);
  options.idw_radius = args.idw_radius;
  options.fill = args.fill;
  options.fill_radius = args.fill_radius;
  options.minus = args.minus;
  options.hillshade = args.hillshade;
  options.memory_mb = args.memory_mb;
  const RasterReport report = buildRaster(options);
  if (!args.quiet) {
    std::fprintf(stderr,
                 "%s: %lld x %lld cells of %g from (%.17g, %.17g), %llu with a value%s; %llu "
                 "points read, %llu in cells, %llu pass(es); CRS %s\n",
                 args.output.c_str(), static_cast<long long>(report.grid.columns),
                 static_cast<long long>(report.grid.rows), report.grid.resolution, report.grid.left,
                 report.grid.top, static_cast<unsigned long long>(report.cells_with_value),
                 report.cells_filled
                     ? (" (" + std::to_string(report.cells_filled) + " filled)").c_str()
                     : "",
                 static_cast<unsigned long long>(report.points_read),
                 static_cast<unsigned long long>(report.points_used),
                 static_cast<unsigned long long>(report.bands), report.crs.c_str());
    if (!report.hillshade.empty()) {
      std::fprintf(stderr, "hillshade: %s\n", report.hillshade.c_str());
    }
  }
  return 0;
}

}  // namespace

Command addRasterCommand(CLI::App& app) {
  auto args = std::make_shared<RasterArgs>();
  CLI::App* sub = app.add_subcommand(
      "raster",
      "A float32 GeoTIFF of one value a cell (DTM: --classes 2 --value min; DSM: --returns first "
      "--value max; CHM: a DSM --minus the DTM), tiled, compressed, with nodata -9999 and the "
      "cloud's CRS, streamed out of core within --memory");
  sub->add_option("input", args->input, "Input point file (PLY, LAS, LAZ, COPC, text, ...)")
      ->required();
  sub->add_option("-o,--output", args->output, "Output GeoTIFF")->required();
  sub->add_option("--resolution", args->resolution,
                  "Cell size in the cloud's horizontal unit; cell edges on multiples of it "
                  "(a point on an edge belongs to the cell at its right, or above it)")
      ->required();
  sub->add_option("--value", args->value,
                  "What a cell holds: min, max, mean (z), idw (inverse distance squared of the "
                  "points within --idw-radius of the cell's centre, as gdal_grid invdist), count, "
                  "density (points per square unit), intensity (mean); default min");
  sub->add_option("--bounds", args->bounds,
                  "XMIN,YMIN,XMAX,YMAX: the raster's extent, edges from XMIN and YMIN (default: "
                  "the cloud's, aligned to the resolution)");
  sub->add_option("--idw-radius", args->idw_radius,
                  "--value idw: the search radius around a cell's centre (default: the "
                  "resolution)");
  sub->add_flag("--fill", args->fill,
                "Fill cells without a value by inverse distance squared from the cells with "
                "one within --fill-radius");
  sub->add_option("--fill-radius", args->fill_radius,
                  "--fill: how far to look for values (default: 10 cells)");
  sub->add_option("--minus", args->minus,
                  "Subtract this raster of the same grid (a DTM from a DSM: a canopy height "
                  "model); nodata where either has none");
  sub->add_flag("--hillshade", args->hillshade,
                "Also write OUT_hillshade.png: shaded relief as gdaldem hillshade (Horn, "
                "azimuth 315, altitude 45)");
  sub->add_option("--memory", args->memory_mb,
                  "Memory budget in MB for the grid (default 2048); a larger grid is made in "
                  "bands of rows, the cloud read once a band")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 24));
  sub->add_option("--columns", args->columns,
                  "Text input: the columns' names, e.g. x,y,z,i (_ skips a column)")
      ->delimiter(',');
  addFilterOptions(*sub, args->filter_options, "used (--returns all: every return)");
  addQuietFlag(*sub, args->quiet);
  Command command;
  command.subcommand = sub;
  command.run = [args] { return runRasterCommand(*args); };
  return command;
}

}  // namespace parallax::cli
