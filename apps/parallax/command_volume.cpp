// `parallax volume IN --polygon P.geojson [--base plane|lowest|FILE.tif]`: cut, fill and net
// volume between the cloud's surface and a base inside a polygon (raster/volume.h).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_options.h"
#include "progress_options.h"
#include "raster/volume.h"

namespace parallax::cli {

namespace {

struct VolumeArgs {
  std::string input;
  std::string polygon;
  std::string base = "plane";
  double resolution = 0.5;
  std::string surface = "max";
  double fill_radius = 0.0;
  std::string raster_out;
  std::vector<std::string> columns;
  FilterOptions filter_options;
  bool json = false;
};

const char* baseName(VolumeBase base) {
  switch (base) {
    case VolumeBase::Plane:
      return "plane";
    case VolumeBase::Lowest:
      return "lowest";
    case VolumeBase::Raster:
      return "raster";
  }
  return "?";
}

int runVolumeCommand(const VolumeArgs& args) {
  VolumeOptions options;
  options.input.path = args.input;
  options.input.text_columns = args.columns;
  options.input.filter = pointFilterFrom(args.filter_options, FilterTarget::Cpu);
  options.polygon = readPolygonFile(args.polygon);
  options.resolution = args.resolution;
  if (args.surface == "max") {
    options.surface = RasterValue::Max;
  } else if (args.surface == "mean") {
    options.surface = RasterValue::Mean;
  } else {
    throw std::invalid_argument("--surface: expected max or mean, found '" + args.surface + "'");
  }
  setVolumeBase(options, args.base);  // a raster's file is checked by computeVolume
  options.fill_radius = args.fill_radius;
  options.raster_out = args.raster_out;
  const VolumeReport r = computeVolume(options);
  if (args.json) {
    nlohmann::json out = {
        {"cut", r.cut},
        {"fill", r.fill},
        {"net", r.net},
        {"area", r.area},
        {"cells", r.cells},
        {"resolution", r.grid.resolution},
        {"surface", args.surface},
        {"base", baseName(options.base)},
        {"cells_filled", r.cells_filled},
        {"cells_without_surface", r.cells_without_surface},
        {"cells_without_base", r.cells_without_base},
        {"points_used", r.points_used},
    };
    if (options.base != VolumeBase::Raster) {
      out["plane"] = {r.plane_a, r.plane_b, r.plane_c};
      out["boundary_samples"] = r.boundary_samples;
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("cut  %.6g\nfill %.6g\nnet  %.6g\narea %.6g (%llu cells of %g)\n", r.cut, r.fill,
              r.net, r.area, static_cast<unsigned long long>(r.cells), r.grid.resolution);
  if (options.base != VolumeBase::Raster) {
    std::printf("base z = %.9g x + %.9g y + %.9g (%llu samples along the ring)\n", r.plane_a,
                r.plane_b, r.plane_c, static_cast<unsigned long long>(r.boundary_samples));
  }
  if (r.cells_without_surface || r.cells_without_base) {
    std::fprintf(stderr, "left out: %llu cells without surface, %llu without base\n",
                 static_cast<unsigned long long>(r.cells_without_surface),
                 static_cast<unsigned long long>(r.cells_without_base));
  }
  return 0;
}

}  // namespace

Command addVolumeCommand(CLI::App& app) {
  auto args = std::make_shared<VolumeArgs>();
  CLI::App* sub = app.add_subcommand(
      "volume",
      "Cut, fill and net volume between the cloud's surface (highest point a cell, gaps "
      "filled) and a base, over the cells whose centre is inside a polygon");
  sub->add_option("input", args->input, "Input point file (PLY, LAS, LAZ, COPC, text, ...)")
      ->required();
  sub->add_option("--polygon", args->polygon,
                  "The region: GeoJSON Polygon or a text file of x y vertices, in the cloud's "
                  "coordinates")
      ->required();
  sub->add_option("--base", args->base,
                  "plane (least squares through the surface along the polygon's ring, default), "
                  "lowest (horizontal at the ring's lowest sample) or a raster file (a DTM)");
  sub->add_option("--resolution", args->resolution, "Cell size of the surface (default 0.5)");
  sub->add_option("--surface", args->surface,
                  "max (highest point a cell, default) or mean (for a dense, clean cloud)");
  sub->add_option("--fill-radius", args->fill_radius,
                  "How far surface gaps are filled from (default: 10 cells)");
  sub->add_option("--raster-out", args->raster_out,
                  "Write the surface - base raster used (GeoTIFF; nodata outside the polygon)");
  sub->add_option("--columns", args->columns, "Text input: the columns' names")->delimiter(',');
  addFilterOptions(*sub, args->filter_options, "used");
  sub->add_flag("--json", args->json, "Print the result as JSON");
  Command command;
  command.subcommand = sub;
  command.run = [args] { return runVolumeCommand(*args); };
  return command;
}

}  // namespace parallax::cli
