// `parallax process`: steps (process_steps.h) run in order on one or more point files, out of
// core, and the result written as a point file.
//
// How: the inputs' positions are spilled into slabs of x (tile_set.h) sized by the memory
// budget; each step reads the slabs with the halo its neighbourhoods need and writes per-point
// records (kept, normal, curvature, distance, mark) beside them; at the end the inputs are read
// once more and every point that is still kept is written with all its attributes, plus those
// the steps added. Every answer is exact whatever the tiling (the halo grows until the
// neighbourhood is whole, ties go to the smaller index, sums over the cloud are in integers), so
// the output's bytes do not depend on `memory_mb`.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/point_file.h"
#include "lod/convert_stages.h"
#include "lod/output_kind.h"
#include "process/process_steps.h"
#include "process/tile_set.h"

namespace parallax {

struct ProcessOptions {
  std::vector<ConvertInput> inputs;  // read in order, as one cloud
  std::filesystem::path output;      // a point file, COPC file or Potree directory
                                     // (lod/output_kind.h)
  std::vector<ProcessStep> steps;
  std::uint64_t memory_mb = 2048;  // what the tiles may take
  PointWriteOptions write;         // its progress is set by the run
  ProgressFactory progress;        // one sink per stage ("reading", "tiling", a step, "writing")
  // Set (from another thread) to stop the run: it is checked at every tile of every step and
  // every batch read or written (where the stages report progress), and inside an octree build
  // at every batch, chunk or node (lod/octree_build_options.h); the run then throws
  // ProcessCancelled, its work folder and unfinished output removed. Null: not cancellable.
  const std::atomic<bool>* cancel = nullptr;
};

// What runProcess throws when ProcessOptions::cancel was set.
struct ProcessCancelled : std::runtime_error {
  ProcessCancelled() : std::runtime_error("process: cancelled") {}
};

struct ProcessReport {
  std::uint64_t input_points = 0;
  std::uint64_t output_points = 0;
  std::size_t tiles = 0;
  std::vector<std::string> losses;  // what the output's format drops (describeWriteLosses)
  // What the neighbourhood steps' rounds after each tile's first loaded (tile_queries.h): the
  // points beyond a slab and its halo that a run holds at once.
  TileStatistics later_rounds;
};

// Bytes a point of a tile takes while a step works on it (its record, the grid's copy and sort
// keys, a halo, the step's records): the tile size is memory_mb / this.
constexpr std::uint64_t kProcessBytesPerPoint = 256;

// Checks the steps and output before any work (std::invalid_argument naming the step), runs them
// and writes the output (temporary file, renamed when complete). A point file is written as the
// last pass reads the inputs (PLY, LAS, LAZ; text is held whole); an octree is built by lod's
// converters (potree_converter.h, copc_converter.h, within memory_mb) from a LAS file of the
// result written that way in the work folder. The work folder is a hidden
// ".NAME.process-PID" beside the output, removed at the end. Input errors are InputError.
ProcessReport runProcess(const ProcessOptions& options);

}  // namespace parallax
