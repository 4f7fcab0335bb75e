// `parallax convert IN -o OUT`: converts between any two point formats of the format table
// (io/point_format.h), keeping every attribute the target can hold and saying which ones it drops.
// `parallax convert IN... -o DIR`: builds the level-of-detail octree of one or more point files
// as a Potree 2.0 directory (lod/potree_converter.h), out of core within --memory.
// `parallax convert IN... -o OUT.copc.laz`: the same octree as a COPC file (lod/copc_converter.h).
// Between the two octree formats (`convert X.copc.laz -o DIR`, `convert DIR -o X.copc.laz`) the
// tree is re-encoded node by node, not rebuilt, unless --spacing asks for another tree or the
// Potree root box is not a cube (COPC's is).
// `parallax convert OCTREE -o OUT`: a Potree 2.0 directory or its http(s) URL copied to a
// directory, or its points written to a file (octree_export.h).
// --classes and --clip-box (filter_options.h) keep only the matching points on every path: the
// octree builds filter where the inputs stream in (lod/convert_stages.h PointStream), so that
// counts, bounds and spacing are those of the kept points; an octree input is then rebuilt, not
// copied or re-encoded node by node; the file-to-file path filters the cloud it reads whole.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "convert_task.h"
#include "core/error.h"
#include "core/progress.h"
#include "filter_options.h"
#include "io/partial_output.h"
#include "io/point_file.h"
#include "lod/copc_converter.h"
#include "lod/copc_reader.h"
#include "lod/copc_writer.h"
#include "lod/octree_url.h"
#include "lod/output_kind.h"
#include "lod/potree_converter.h"
#include "lod/potree_octree_writer.h"
#include "lod/potree_reader.h"
#include "octree_export.h"
#include "progress_options.h"

namespace parallax::cli {
namespace {

struct ConvertArgs {
  std::vector<std::string> inputs;
  std::string input;  // inputs[0] for the file-to-file conversion
  std::string output;
  std::string format;  // "potree", "copc", or empty: from the output's extension
  bool verbose = false;
  std::uint64_t memory_mb = 2048;
  std::string sampling = "poisson";
  double spacing = 0.0;
  int threads = 0;
  std::vector<std::string> columns;
  std::vector<std::string> properties;  // PLY and text output: these attributes, in this order
  std::string las_version;
  int point_format = -1;  // --point-format; -1: the input's, or chosen
  std::uint32_t laz_chunk = 50000;
  bool ascii = false;
  std::string pcd_data = "binary";  // PCD output: ascii, binary or binary_compressed
  bool quiet = false;
  bool clean =
      false;  // --clean: remove the output's stale partial outputs (and stop without inputs)
  FilterOptions filter_options;
  PointFilter filter;  // parsed from filter_options by runConvert
  bool plan = false;   // --plan: write a distributed conversion's plan (convert_task.h)
  std::size_t tasks = 0;
  std::size_t build_tasks = 0;
  std::string work_dir;
};

// The inputs of an octree build, each with the points to keep.
std::vector<ConvertInput> convertInputs(const ConvertArgs& args) {
  std::vector<ConvertInput> inputs;
  for (const std::string& input : args.inputs) inputs.push_back({input, args.columns, args.filter});
  return inputs;
}

// Removes what killed conversions to `output` left (io/partial_output.h) and says so, unless quiet.
void cleanPartialOutputs(const std::string& output, bool quiet) {
  const PartialCleanup cleanup = removeStalePartialOutputs(output);
  if (quiet) return;
  for (const PartialOutput& partial : cleanup.removed) {
    std::fprintf(stderr, "removed %s, left by a killed conversion (process %d is gone): %s\n",
                 partial.path.string().c_str(), int(partial.pid),
                 formatBytes(partial.bytes).c_str());
  }
  for (const PartialOutput& partial : cleanup.running) {
    std::fprintf(stderr, "left %s: process %d is still running (%s so far)\n",
                 partial.path.string().c_str(), int(partial.pid),
                 formatBytes(partial.bytes).c_str());
  }
  if (!cleanup.removed.empty()) {
    std::fprintf(stderr, "freed %llu bytes (%s) of partial outputs\n",
                 static_cast<unsigned long long>(cleanup.freed_bytes),
                 formatBytes(cleanup.freed_bytes).c_str());
  }
}

PotreeConvertOptions buildOptions(const ConvertArgs& args) {
  PotreeConvertOptions options;
  parseSamplingMethod(args.sampling, options.build.sampling);
  options.build.spacing = args.spacing;
  options.build.memory_bytes = args.memory_mb << 20;
  options.build.threads = args.threads;
  options.progress = stageBars(args.quiet);
  return options;
}

// A COPC file to a Potree directory, node by node (the same tree).
int runCopcToPotree(const ConvertArgs& args) {
  const std::string& input = args.inputs.front();
  std::unique_ptr<Octree> octree = openCopc(input);
  const auto progress = progressBar(args.quiet, "re-encoding nodes", octree->info().point_count);
  PotreeWriteOptions options;
  options.batch_points = copcBatchPoints(args.memory_mb << 20);
  options.progress = progress.get();
  const PotreeWriteResult result = writePotree(*octree, args.output, options);
  if (!args.quiet) {
    std::fprintf(stderr,
                 "wrote %s: Potree 2.0, %llu points, %zu nodes (depth %d), the tree of %s "
                 "re-encoded node by node\n",
                 args.output.c_str(), static_cast<unsigned long long>(result.points), result.nodes,
                 result.depth, input.c_str());
  }
  return 0;
}

void reportCopc(const ConvertArgs& args, const CopcWriteResult& result, const std::string& how) {
  if (args.quiet) return;
  std::fprintf(stderr,
               "wrote %s: COPC 1.0, point format %d, %llu points, %zu nodes in %zu hierarchy "
               "pages, %llu bytes, %s\n",
               args.output.c_str(), result.point_format,
               static_cast<unsigned long long>(result.points), result.nodes, result.pages,
               static_cast<unsigned long long>(result.bytes), how.c_str());
}

int runCopcConvert(const ConvertArgs& args) {
  if (!args.properties.empty()) {
    throw std::invalid_argument(
        "--properties: a COPC file holds every attribute its point format has; the option is for "
        "PLY and text outputs");
  }
  cleanPartialOutputs(args.output, args.quiet);
  const std::vector<ConvertInput> inputs = convertInputs(args);
  // A Potree directory whose layout COPC can hold, all its points kept: node by node.
  if (inputs.size() == 1 && isPotreeDirectory(inputs[0].path) && args.spacing == 0.0 &&
      args.filter.keepsAll()) {
    std::unique_ptr<Octree> octree = openPotree(inputs[0].path);
    const std::optional<std::string> problem = copcLayoutProblem(octree->info());
    if (!problem) {
      const auto progress =
          progressBar(args.quiet, "re-encoding nodes", octree->info().point_count);
      CopcWriteOptions options;
      options.batch_points = copcBatchPoints(args.memory_mb << 20);
      options.progress = progress.get();
      const CopcWriteResult result = writeCopc(*octree, args.output, options);
      reportCopc(args, result, "the tree of " + args.inputs[0] + " re-encoded node by node");
      return 0;
    }
    if (!args.quiet) {
      std::fprintf(stderr, "%s: %s: rebuilding the tree\n", args.inputs[0].c_str(),
                   problem->c_str());
    }
  }
  CopcConvertOptions options;
  options.potree = buildOptions(args);
  const CopcConvertResult result = convertToCopc(inputs, args.output, options);
  if (!args.quiet) {
    for (const std::string& note : result.notes) {
      std::fprintf(stderr, "not carried over: %s\n", note.c_str());
    }
    char how[256];
    std::snprintf(how, sizeof how,
                  "%.2f s (%.2f M points/s; build %.2f s, of which scan %.2f, count %.2f, "
                  "distribute %.2f, chunks %.2f; COPC %.2f s)",
                  result.seconds_total, double(result.copc.points) / result.seconds_total / 1e6,
                  result.build.seconds_total, result.build.seconds_scan, result.build.seconds_count,
                  result.build.seconds_distribute, result.build.seconds_build,
                  result.seconds_write);
    reportCopc(args, result.copc, how);
  }
  return 0;
}

int runPotreeConvert(const ConvertArgs& args) {
  if (!args.properties.empty()) {
    throw std::invalid_argument(
        "--properties: a Potree octree holds every attribute in Potree's order; the option is for "
        "PLY and text outputs");
  }
  if (args.inputs.size() == 1 && isCopcFile(args.inputs[0]) && args.spacing == 0.0 &&
      args.filter.keepsAll()) {
    return runCopcToPotree(args);
  }
  const PotreeConvertOptions options = buildOptions(args);
  const std::vector<ConvertInput> inputs = convertInputs(args);
  cleanPartialOutputs(args.output, args.quiet);
  const PotreeConvertResult result = convertToPotree(inputs, args.output, options);
  if (!args.quiet && !result.crs.empty()) {
    std::fprintf(stderr, "coordinate reference system %s: %s\n", result.crs.summary().c_str(),
                 potreeProjection(result.crs.description).empty()
                     ? "not in metadata.json \"projection\" (a user-defined CRS has no name there)"
                     : "written as metadata.json \"projection\"");
  }
  if (!args.quiet) {
    std::fprintf(stderr,
                 "wrote %s: Potree 2.0, %llu points, %zu nodes (depth %d) from %zu chunks, "
                 "%.2f s (%.2f M points/s; scan %.2f s, count %.2f s, distribute %.2f s, "
                 "build %.2f s)\n",
                 args.output.c_str(), static_cast<unsigned long long>(result.points), result.nodes,
                 result.depth, result.chunks, result.seconds_total,
                 double(result.points) / result.seconds_total / 1e6, result.seconds_scan,
                 result.seconds_count, result.seconds_distribute, result.seconds_build);
  }
  return 0;
}

[[noreturn]] void throwUnknownOutput(const std::string& output) {
  const std::filesystem::path path(output);
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  const std::string octree = path.stem().string() + extension + "/";
  throw InputError(
      {.file = output,
       .expected = "an output name ending in " + writableExtensionsText() +
                   " or .copc.laz, or a Potree 2.0 octree directory (--format potree, a name "
                   "ending in '/', an existing directory, or a name without extension)",
       .found = "'" + path.extension().string() + "'",
       .hint = "for an octree, add --format potree (or write -o " + octree + ")"});
}

int runConvert(ConvertArgs args) {
  if (args.inputs.empty()) {
    if (!args.clean) {
      throw std::invalid_argument("convert: no input (give point files, or --clean -o OUTPUT)");
    }
    cleanPartialOutputs(args.output, args.quiet);
    return 0;
  }
  args.filter =
      pointFilterFrom(args.filter_options, FilterTarget::Cpu);  // before any output is touched
  const bool filtered = !args.filter.keepsAll();
  if (args.plan) {
    return runConvertPlan({.inputs = args.inputs,
                           .columns = args.columns,
                           .output = args.output,
                           .work_dir = args.work_dir,
                           .filter_options = args.filter_options,
                           .build = buildOptions(args).build,
                           .tasks = args.tasks,
                           .build_tasks = args.build_tasks,
                           .quiet = args.quiet});
  }
  // The output's kind, by the rule process shares (lod/output_kind.h).
  const OutputKind kind = outputKind(args.output, args.format);
  if (kind == OutputKind::kCopc) return runCopcConvert(args);
  const bool to_potree = kind == OutputKind::kPotree;
  const bool one_input = args.inputs.size() == 1;
  if (one_input && to_potree && isCopcFile(args.inputs.front())) return runPotreeConvert(args);
  if (one_input && isPotreeDirectory(args.inputs.front()) &&
      !(to_potree && (args.spacing != 0.0 || filtered))) {
    // An octree (a Potree directory or its URL) in: copied, or its points written to a file.
    return runOctreeExport({.input = args.inputs.front(),
                            .output = args.output,
                            .to_directory = to_potree,
                            .ply_ascii = args.ascii,
                            .las_minor_version = args.las_version == "1.4"   ? 4
                                                 : args.las_version == "1.2" ? 2
                                                                             : 0,
                            .quiet = args.quiet,
                            .verbose = args.verbose,
                            .filter = args.filter});
  }
  if (one_input && !to_potree && octreeUrlKind(args.inputs.front()) == OctreeUrlKind::Copc) {
    // A COPC file's URL to a point file: through its octree, reading only the nodes the filter
    // may keep points of (a local COPC file is read as the LAZ file it also is, below).
    return runOctreeExport({.input = args.inputs.front(),
                            .output = args.output,
                            .ply_ascii = args.ascii,
                            .las_minor_version = args.las_version == "1.4"   ? 4
                                                 : args.las_version == "1.2" ? 2
                                                                             : 0,
                            .quiet = args.quiet,
                            .verbose = args.verbose,
                            .filter = args.filter});
  }
  if (to_potree) return runPotreeConvert(args);
  if (args.inputs.size() != 1) {
    throw InputError({.file = args.output,
                      .expected = "one input when converting to a point file",
                      .found = std::to_string(args.inputs.size()) + " inputs",
                      .hint = "several inputs merge only into a Potree directory (--format "
                              "potree, or an output name ending in '/')"});
  }
  args.input = args.inputs.front();
  // Both ends through the format table (io/point_format.h): the input's row by content, the
  // output's by extension.
  const PointFormat in_format = detectPointFormat(args.input);
  const PointFormatEntry* out_row = formatForExtension(args.output).entry();
  if (out_row == nullptr || !out_row->write) throwUnknownOutput(args.output);  // before the read
  if (!args.properties.empty() && out_row->fixed_layout && out_row->fixed_layout(args.output)) {
    throw std::invalid_argument("--properties: " + args.output + " has a fixed record layout (" +
                                out_row->name +
                                "); the option is for outputs that choose their "
                                "attributes' order (PLY, text)");
  }
  cleanPartialOutputs(args.output, args.quiet);
  PointCloud cloud;
  {
    const auto progress = readingBar(args.quiet, "reading", args.input);
    cloud = readPointFile(args.input, {.progress = progress.get(), .text_columns = args.columns});
  }
  const std::uint64_t read_points = cloud.count;
  if (filtered) {
    cloud = filterPoints(cloud, args.filter);
    // As the octree builds say (lod/convert_count.cpp): an empty output is a mistake, not a result.
    if (cloud.count == 0) {
      throw InputError(
          {.file = args.input,
           .expected =
               "at least one point that the filters (classes, returns, ranges, clip region) keep",
           .found = "none of " + std::to_string(read_points) + " points",
           .hint = "check the class list and the clip box against the input's "
                   "classes and bounds (parallax info)"});
    }
  }
  int minor = 0;
  if (args.las_version == "1.2") minor = 2;
  if (args.las_version == "1.3") minor = 3;
  if (args.las_version == "1.4") minor = 4;
  // The source travels with the options: what the output keeps of its header (a LAS output
  // its CRS) is the output row's decision.
  const PointWriteOptions write_options{.ply_ascii = args.ascii,
                                        .las_minor_version = minor,
                                        .las_point_format = args.point_format,
                                        .laz_chunk_points = args.laz_chunk,
                                        .pcd_data = args.pcd_data == "ascii" ? PcdData::Ascii
                                                    : args.pcd_data == "binary"
                                                        ? PcdData::Binary
                                                        : PcdData::BinaryCompressed,
                                        .properties = args.properties,
                                        .source = args.input};

  std::vector<std::string> losses = describeWriteLosses(cloud, args.output, write_options);
  if (!args.properties.empty()) {
    std::vector<std::string> kept;
    try {
      kept = cloud.attributeOrder(args.properties);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--properties: ") + e.what());
    }
    std::string left_out;
    for (const std::string& name : cloud.attributeNames()) {
      if (std::find(kept.begin(), kept.end(), name) == kept.end()) {
        left_out += (left_out.empty() ? "" : " ") + name;
      }
    }
    if (!left_out.empty()) losses.push_back(left_out + " (not in --properties)");
  }
  if (!args.quiet) {
    std::fprintf(stderr, "%s: %s, %llu points\n", args.input.c_str(),
                 pointFormatName(in_format).c_str(), static_cast<unsigned long long>(read_points));
    if (filtered) {
      std::fprintf(stderr, "kept %llu points (--classes, --clip-box)\n",
                   static_cast<unsigned long long>(cloud.count));
    }
    for (const std::string& loss : losses) {
      std::fprintf(stderr, "dropped or changed: %s\n", loss.c_str());
    }
  }

  const auto progress = progressBar(args.quiet, "writing", cloud.count);
  PointWriteOptions options = write_options;
  options.progress = progress.get();
  writePointFile(cloud, args.output, options);
  if (progress) progress->finish();
  if (!args.quiet) std::fprintf(stderr, "wrote %s\n", args.output.c_str());
  return 0;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  Command command;
  CLI::App* sub = app.add_subcommand(
      "convert",
      "Convert a point file between " + pointFormatNamesText() +
          ", or point files to a level-of-detail octree: a Potree 2.0 directory or a COPC file "
          "(.copc.laz)");
  sub->add_option("input", args->inputs,
                  "Input point files (format detected from their content), a Potree directory (or "
                  "its http(s) URL) or a COPC file; several only for an octree, where they are "
                  "merged; one octree is copied, or its points written to a file");
  sub->add_option("-o,--output", args->output,
                  "Output file, its extension picks the format (" + writableExtensionsText() +
                      "), .copc.laz: a COPC octree, or a Potree 2.0 octree directory: a name "
                      "ending in '/', an existing directory, a name without extension, or "
                      "--format potree")
      ->required();
  sub->add_option("--format", args->format,
                  "Force an octree output: potree (a directory) or copc, whatever the output's "
                  "name")
      ->check(CLI::IsMember({"potree", "copc"}));
  sub->add_option("--memory", args->memory_mb, "Octree output: memory budget in MB (default 2048)")
      ->check(CLI::Range(std::uint64_t(16), std::uint64_t(1) << 24));
  sub->add_option("--sampling", args->sampling,
                  "Octree output: poisson (even, default) or random (faster)")
      ->check(CLI::IsMember({"poisson", "random"}));
  sub->add_option("--spacing", args->spacing,
                  "Octree output: root spacing in world units (default: cube edge / 128; an octree "
                  "input is then rebuilt)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", args->threads, "Octree output: worker threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--columns", args->columns,
                  "Text input: the columns' names, e.g. x,y,z,r,g,b (_ skips a column)")
      ->delimiter(',');
  sub->add_option("--properties", args->properties,
                  "PLY and text output: the attributes to write, in this order, e.g. "
                  "x,y,z,red,green,blue,nx,ny,nz (default: all, in the input's order)")
      ->delimiter(',');
  sub->add_option("--las-version", args->las_version,
                  "LAS output: 1.2, 1.3 or 1.4 (default: a LAS input's; else 1.2 unless the "
                  "attributes need 1.4)")
      ->check(CLI::IsMember({"1.2", "1.3", "1.4"}));
  sub->add_option("--point-format", args->point_format,
                  "LAS output: the point data record format 0-10 (default: a LAS input's, "
                  "grown only when the points have a field it lacks; else chosen from the "
                  "attributes)")
      ->check(CLI::Range(0, 10));
  sub->add_option("--laz-chunk", args->laz_chunk,
                  "LAZ output: points a chunk (default 50000, LASzip's)")
      ->check(CLI::Range(std::uint32_t(1), std::uint32_t(100'000'000)));
  sub->add_flag("--ascii", args->ascii,
                "PLY output: ascii instead of binary little endian; PCD output: DATA ascii");
  sub->add_option("--pcd-data", args->pcd_data,
                  "PCD output: the DATA encoding, ascii, binary (default) or binary_compressed")
      ->check(CLI::IsMember({"ascii", "binary", "binary_compressed"}));
  addFilterOptions(*sub, args->filter_options, "written");
  sub->add_flag("--plan", args->plan,
                "Octree output: write the plan of a distributed build (WORK/plan.json) instead "
                "of building; parallax convert-task runs its tasks (python3 -m parallax_dask "
                "runs them all on a Dask cluster)");
  sub->add_option("--tasks", args->tasks,
                  "--plan: split the inputs into about this many ranges, the chunks into as many "
                  "build groups (default: 4 per core)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20));
  sub->add_option("--build-tasks", args->build_tasks,
                  "--plan: group the chunks into about this many build tasks (default: --tasks)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20));
  sub->add_option("--work-dir", args->work_dir,
                  "--plan: the work directory shared by the tasks (default: .OUTPUT.work beside "
                  "the output)");
  addQuietFlag(*sub, args->quiet);
  sub->add_flag("-v,--verbose", args->verbose,
                "An octree (or its URL) to a point file: report the nodes read and the bytes the "
                "network fetched");
  sub->add_flag("--clean", args->clean,
                "Remove the partial outputs killed conversions to -o OUTPUT left (hidden "
                ".OUTPUT.partial-PID), whose process is gone, and say how much that freed; "
                "without inputs, only that (every conversion does it first anyway)");
  command.subcommand = sub;
  command.run = [args] { return runConvert(*args); };
  return command;
}

}  // namespace parallax::cli
