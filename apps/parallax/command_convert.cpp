// `parallax convert IN -o OUT`: converts between any two supported point formats (PLY, LAS,
// text), keeping every attribute the target can hold and saying which ones it drops.
// `parallax convert IN... -o DIR`: builds the level-of-detail octree of one or more point files
// as a Potree 2.0 directory (lod/potree_converter.h), out of core within --memory.
// `parallax convert OCTREE -o OUT`: a Potree 2.0 directory or its http(s) URL copied to a
// directory, or its points written to a file (octree_export.h).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "core/progress.h"
#include "io/las_header.h"
#include "io/las_writer.h"
#include "io/point_file.h"
#include "lod/octree_url.h"
#include "lod/potree_converter.h"
#include "lod/potree_reader.h"
#include "octree_export.h"

namespace parallax::cli {
namespace {

struct ConvertArgs {
  std::vector<std::string> inputs;
  std::string input;  // inputs[0] for the file-to-file conversion
  std::string output;
  std::string format;  // "potree", or empty: from the output's extension
  std::uint64_t memory_mb = 2048;
  std::string sampling = "poisson";
  double spacing = 0.0;
  int threads = 0;
  std::vector<std::string> columns;
  std::string las_version;
  bool ascii = false;
  bool quiet = false;
};

int runPotreeConvert(const ConvertArgs& args) {
  PotreeConvertOptions options;
  parseSamplingMethod(args.sampling, options.build.sampling);
  options.build.spacing = args.spacing;
  options.build.memory_bytes = args.memory_mb << 20;
  options.build.threads = args.threads;
  if (!args.quiet) {
    options.progress = [](const std::string& stage, std::uint64_t total) {
      return std::make_unique<TerminalProgress>(stage, total);
    };
  }
  std::vector<ConvertInput> inputs;
  for (const std::string& input : args.inputs) inputs.push_back({input, args.columns});
  const PotreeConvertResult result = convertToPotree(inputs, args.output, options);
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

int runConvert(ConvertArgs args) {
  const bool to_potree =
      args.format == "potree" ||
      (args.format.empty() && formatForExtension(args.output) == PointFormat::Unknown &&
       !std::filesystem::path(args.output).has_extension());
  for (const std::string& input : args.inputs) checkOctreeUrl(input);
  if (args.inputs.size() == 1 && isPotreeDirectory(args.inputs.front())) {
    // An octree (a Potree directory or its URL) in: copied, or its points written to a file.
    return runOctreeExport({.input = args.inputs.front(),
                            .output = args.output,
                            .to_directory = to_potree,
                            .ply_ascii = args.ascii,
                            .las_minor_version = args.las_version == "1.4"   ? 4
                                                 : args.las_version == "1.2" ? 2
                                                                             : 0,
                            .quiet = args.quiet});
  }
  if (to_potree) return runPotreeConvert(args);
  if (args.inputs.size() != 1) {
    throw InputError({.file = args.output,
                      .expected = "one input when converting to a point file",
                      .found = std::to_string(args.inputs.size()) + " inputs",
                      .hint = "several inputs merge only into a Potree directory (an output "
                              "without extension, or --format potree)"});
  }
  args.input = args.inputs.front();
  PointFormat in_format = detectPointFormat(args.input);
  PointFormat out_format = formatForExtension(args.output);
  if (out_format == PointFormat::Unknown) {
    // writePointFile reports the supported extensions; fail before the (long) read.
    writePointFile(PointCloud{}, args.output);
  }
  PointCloud cloud;
  {
    std::optional<TerminalProgress> progress;
    if (!args.quiet)
      progress.emplace("reading", 0, in_format == PointFormat::Text ? "bytes" : "points");
    cloud = readPointFile(
        args.input, {.progress = progress ? &*progress : nullptr, .text_columns = args.columns});
  }
  int minor = 0;
  if (args.las_version == "1.2") minor = 2;
  if (args.las_version == "1.4") minor = 4;

  std::vector<std::string> losses = describeWriteLosses(
      cloud, args.output, {.ply_ascii = args.ascii, .las_minor_version = minor});
  LasHeader source_header;
  bool from_las = in_format == PointFormat::Las;
  if (from_las) {
    source_header = readLasHeader(args.input);
    if (!source_header.crs.empty() && out_format != PointFormat::Las) {
      losses.push_back("the coordinate reference system (" + source_header.crs.summary() +
                       "): " + pointFormatName(out_format) + " has no place for it");
    }
  }
  if (!args.quiet) {
    std::fprintf(stderr, "%s: %s, %llu points\n", args.input.c_str(), pointFormatName(in_format),
                 static_cast<unsigned long long>(cloud.count));
    for (const std::string& loss : losses) {
      std::fprintf(stderr, "dropped or changed: %s\n", loss.c_str());
    }
  }

  std::optional<TerminalProgress> progress;
  if (!args.quiet) progress.emplace("writing", cloud.count);
  Progress* sink = progress ? &*progress : nullptr;
  if (out_format == PointFormat::Las) {
    LasWriteOptions options{.minor_version = minor, .progress = sink};
    if (from_las) {
      // Keep the CRS records and the GPS time type of a LAS source.
      for (const LasVlr& vlr : source_header.vlrs) {
        if (vlr.user_id == "LASF_Projection" && !vlr.data.empty()) options.vlrs.push_back(vlr);
      }
      options.gps_time_standard = source_header.gpsTimeIsStandard();
      options.file_source_id = source_header.file_source_id;
    }
    writeLas(cloud, args.output, options);
  } else {
    writePointFile(cloud, args.output,
                   {.progress = sink, .ply_ascii = args.ascii, .las_minor_version = minor});
  }
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
      "Convert a point file between PLY, LAS and text (xyz, txt, csv, pts), or point files to "
      "a Potree 2.0 octree directory");
  sub->add_option("input", args->inputs,
                  "Input point files (format detected from their content); several only for a "
                  "Potree directory, where they are merged; or one Potree 2.0 directory or its "
                  "http(s) URL (copied, or its points written to a file)")
      ->required();
  sub->add_option("-o,--output", args->output,
                  "Output file, its extension picks the format (.ply .las .xyz .txt .csv .asc "
                  ".pts), or a directory (no extension): a Potree 2.0 octree")
      ->required();
  sub->add_option("--format", args->format, "Force the output format: potree")
      ->check(CLI::IsMember({"potree"}));
  sub->add_option("--memory", args->memory_mb, "Potree output: memory budget in MB (default 2048)")
      ->check(CLI::Range(std::uint64_t(16), std::uint64_t(1) << 24));
  sub->add_option("--sampling", args->sampling,
                  "Potree output: poisson (even, default) or random (faster)")
      ->check(CLI::IsMember({"poisson", "random"}));
  sub->add_option("--spacing", args->spacing,
                  "Potree output: root spacing in world units (default: cube edge / 128)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", args->threads, "Potree output: worker threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--columns", args->columns,
                  "Text input: the columns' names, e.g. x,y,z,r,g,b (_ skips a column)")
      ->delimiter(',');
  sub->add_option("--las-version", args->las_version,
                  "LAS output: 1.2 or 1.4 (default: 1.2 unless the attributes need 1.4)")
      ->check(CLI::IsMember({"1.2", "1.4"}));
  sub->add_flag("--ascii", args->ascii, "PLY output: ascii instead of binary little endian");
  sub->add_flag("-q,--quiet", args->quiet, "No progress or report on stderr");
  command.subcommand = sub;
  command.run = [args] { return runConvert(*args); };
  return command;
}

}  // namespace parallax::cli
