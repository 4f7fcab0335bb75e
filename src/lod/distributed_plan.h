// The plan of a conversion to Potree 2.0 split into tasks (`parallax convert --plan`, run by
// `parallax convert-task` on the workers of a Dask cluster: python/parallax_dask), and the files
// the tasks hand each other in the work directory.
//
// The conversion's stages (convert_stages.h) become tasks over ranges of the inputs and groups
// of chunks:
//
//   scan RANGE      the points, bounds of points [first, last) of one input   scan/range_R.json
//   cube            the scans merged: cube, spacing, quantization, layout     cube.json
//   count RANGE     the count grid of one range (non-empty cells only)        count/range_R.bin
//   chunks          the counts merged: the chunks, in groups for the builds   chunks.json
//   distribute RANGE  the range's records, one shard per chunk;              shards/range_R/
//                   its attributes' ranges                                    stats/range_R.bin
//   build GROUP     the chunks of one group: their nodes in octree.bin at     build/octree.bin
//                   their offset if known (topLevelsSplit), else in a part;   build/group_G.*
//                   nodes, roots
//   place GROUP     a part its build could not place copied to its offset     build/octree.bin
//   finish          top levels into the gap, octree.bin moved, hierarchy,     the output
//                   metadata
//
// Every task reads files only and writes its own under a temporary name, renamed when complete:
// run again (after a crash, or twice at once on two workers) it writes the same bytes. The build
// of a chunk reads its shards in range order, which is the order the local build spills the
// points in, so the octree is byte for byte the one `parallax convert` writes on one machine,
// whatever the number of tasks and workers.
//
// Inputs are split where a reader can start inside them without reading what comes before
// (PointStream::canSkip: PLY, LAS); other inputs (text, LAZ, octrees) are one range each.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/quantization.h"
#include "lod/convert_stages.h"
#include "lod/octree_build_options.h"
#include "lod/potree_layout.h"

namespace parallax {

struct PlannedInput {
  std::filesystem::path path;  // absolute
  std::uint64_t points = 0;    // in the file, before filtering
  Quantization quantization;   // as the file's first stream chose it (every task uses it)
  PotreeLayout layout;         // of its points (the attributes it has)
  bool splittable = false;     // PointStream::canSkip
};

// Points [first, last) of input `input`, counted before filtering.
struct InputRange {
  std::size_t input = 0;
  std::uint64_t first = 0, last = 0;
};

struct DistributedPlan {
  std::filesystem::path work_dir;  // absolute; plan.json and every task's files
  std::filesystem::path output;    // absolute; the Potree directory the finish task writes
  std::vector<PlannedInput> inputs;
  std::vector<std::string> text_columns;  // text inputs (point_file.h)
  // The command line's filter options, as given (it builds the PointFilter of each task from
  // them; lod does not read them).
  nlohmann::json filter = nlohmann::json::object();
  OctreeBuildOptions build;  // sampling, spacing, node size, memory, chunk size
  std::string projection;    // metadata.json "projection" (potreeProjection of the inputs' CRS)
  std::vector<InputRange> ranges;
  std::size_t build_tasks = 1;  // groups of chunks the chunks task makes (at most)
};

// Reads the inputs' headers (and what their readers sample to choose a quantization; a text
// input is read once for it) and splits them into about `tasks` ranges of equal point counts.
// Throws InputError as the local conversion does for unreadable inputs and disagreeing CRSs.
DistributedPlan makeDistributedPlan(const std::vector<ConvertInput>& inputs,
                                    const std::filesystem::path& output,
                                    const std::filesystem::path& work_dir,
                                    const OctreeBuildOptions& build, std::size_t tasks);

// plan.json in the work directory (written under a temporary name and renamed).
std::filesystem::path planPath(const std::filesystem::path& work_dir);
void writeDistributedPlan(const DistributedPlan& plan);
// Throws InputError naming the file for a missing or malformed plan.
DistributedPlan readDistributedPlan(const std::filesystem::path& path);

// A count in a task file's JSON: a whole number from 0 to `max`. Anything else (a fraction, a
// negative number, 1e36) throws nlohmann::json::type_error, as another wrong type does;
// converting it as it is would be undefined.
std::uint64_t jsonCount(const nlohmann::json& value,
                        std::uint64_t max = std::numeric_limits<std::uint64_t>::max());

// Writes `bytes` to `path` through a unique temporary name beside it and a rename.
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);
// The whole file; throws std::runtime_error naming it (a task's input that an earlier task
// should have written).
std::string readWholeFile(const std::filesystem::path& path);
// A unique temporary name beside `path` (".NAME.tmp-PID-N").
std::filesystem::path temporaryPathFor(const std::filesystem::path& path);

}  // namespace parallax
