// The distributed conversion on the command line (lod/distributed_plan.h): `parallax convert
// --plan` writes the plan, `parallax convert-task STAGE PLAN --part I` runs one task of it.
// The Dask driver (python/parallax_dask) runs both.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_options.h"
#include "lod/octree_build_options.h"

namespace parallax::cli {

struct ConvertPlanRequest {
  std::vector<std::string> inputs;
  std::vector<std::string> columns;  // text inputs
  std::string output;                // the Potree directory the finish task writes
  std::string work_dir;              // empty: ".NAME.work" beside the output
  FilterOptions filter_options;
  OctreeBuildOptions build;
  std::size_t tasks = 0;        // ranges to aim for; 0: 4 per core of this machine
  std::size_t build_tasks = 0;  // groups of chunks to aim for; 0: as many as ranges
  bool quiet = false;
};

// Writes WORK/plan.json and prints its path on stdout, with the number of ranges. Throws as
// `parallax convert` does for bad inputs.
int runConvertPlan(const ConvertPlanRequest& request);

Command addConvertTaskCommand(CLI::App& app);

}  // namespace parallax::cli
