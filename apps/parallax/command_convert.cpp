// `parallax convert IN -o OUT`: converts between any two supported point formats (PLY, LAS,
// LAZ, text), keeping every attribute the target can hold and saying which ones it drops.
// `parallax convert IN... -o DIR`: builds the level-of-detail octree of one or more point files
// as a Potree 2.0 directory (lod/potree_converter.h), out of core within --memory.
// `parallax convert IN... -o OUT.copc.laz`: the same octree as a COPC file (lod/copc_converter.h).
// Between the two octree formats (`convert X.copc.laz -o DIR`, `convert DIR -o X.copc.laz`) the
// tree is re-encoded node by node, not rebuilt, unless --spacing asks for another tree or the
// Potree root box is not a cube (COPC's is).
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
#include "io/laz_writer.h"
#include "io/point_file.h"
#include "lod/copc_converter.h"
#include "lod/copc_reader.h"
#include "lod/copc_writer.h"
#include "lod/potree_converter.h"
#include "lod/potree_octree_writer.h"
#include "lod/potree_reader.h"

namespace parallax::cli {
namespace {

struct ConvertArgs {
  std::vector<std::string> inputs;
  std::string input;  // inputs[0] for the file-to-file conversion
  std::string output;
  std::string format;  // "potree", "copc", or empty: from the output's extension
  std::uint64_t memory_mb = 2048;
  std::string sampling = "poisson";
  double spacing = 0.0;
  int threads = 0;
  std::vector<std::string> columns;
  std::string las_version;
  std::uint32_t laz_chunk = 50000;
  bool ascii = false;
  bool quiet = false;
};

bool hasCopcName(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
  return name.size() > 9 && name.ends_with(".copc.laz");
}

std::unique_ptr<TerminalProgress> progressFor(const ConvertArgs& args, const char* stage,
                                              std::uint64_t total) {
  if (args.quiet) return nullptr;
  return std::make_unique<TerminalProgress>(stage, total);
}

PotreeConvertOptions buildOptions(const ConvertArgs& args) {
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
  return options;
}

// A COPC file to a Potree directory, node by node (the same tree).
int runCopcToPotree(const ConvertArgs& args) {
  const std::string& input = args.inputs.front();
  std::unique_ptr<Octree> octree = openCopc(input);
  const auto progress = progressFor(args, "re-encoding nodes", octree->info().point_count);
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
  std::vector<ConvertInput> inputs;
  for (const std::string& input : args.inputs) inputs.push_back({input, args.columns});
  // A Potree directory whose layout COPC can hold: node by node.
  if (inputs.size() == 1 && isPotreeDirectory(inputs[0].path) && args.spacing == 0.0) {
    std::unique_ptr<Octree> octree = openPotree(inputs[0].path);
    const std::optional<std::string> problem = copcLayoutProblem(octree->info());
    if (!problem) {
      const auto progress = progressFor(args, "re-encoding nodes", octree->info().point_count);
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
  if (args.inputs.size() == 1 && isCopcFile(args.inputs[0]) && args.spacing == 0.0) {
    return runCopcToPotree(args);
  }
  const PotreeConvertOptions options = buildOptions(args);
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
  if (to_potree) return runPotreeConvert(args);
  if (args.format == "copc" || (args.format.empty() && hasCopcName(args.output))) {
    return runCopcConvert(args);
  }
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
  bool from_las = in_format == PointFormat::Las || in_format == PointFormat::Laz;
  if (from_las) {
    source_header = readLasHeader(args.input);
    if (!source_header.crs.empty() && out_format != PointFormat::Las &&
        out_format != PointFormat::Laz) {
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
  if (out_format == PointFormat::Las || out_format == PointFormat::Laz) {
    LasWriteOptions options{.minor_version = minor, .progress = sink};
    if (from_las) {
      // Keep the CRS records and the GPS time type of a LAS source.
      for (const LasVlr& vlr : source_header.vlrs) {
        if (vlr.user_id == "LASF_Projection" && !vlr.data.empty()) options.vlrs.push_back(vlr);
      }
      options.gps_time_standard = source_header.gpsTimeIsStandard();
      options.file_source_id = source_header.file_source_id;
    }
    if (out_format == PointFormat::Laz) {
      writeLaz(cloud, args.output, {.las = options, .chunk_points = args.laz_chunk});
    } else {
      writeLas(cloud, args.output, options);
    }
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
      "Convert a point file between PLY, LAS, LAZ and text (xyz, txt, csv, pts), or point files to "
      "a level-of-detail octree: a Potree 2.0 directory or a COPC file (.copc.laz)");
  sub->add_option("input", args->inputs,
                  "Input point files (format detected from their content), a Potree directory or a "
                  "COPC file; several only for an octree, where they are merged")
      ->required();
  sub->add_option(
         "-o,--output", args->output,
         "Output file, its extension picks the format (.ply .las .laz .xyz .txt .csv "
         ".asc .pts), a directory (no extension): a Potree 2.0 octree, or .copc.laz: a COPC "
         "octree")
      ->required();
  sub->add_option("--format", args->format, "Force the output format: potree or copc")
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
  sub->add_option("--las-version", args->las_version,
                  "LAS output: 1.2 or 1.4 (default: 1.2 unless the attributes need 1.4)")
      ->check(CLI::IsMember({"1.2", "1.4"}));
  sub->add_option("--laz-chunk", args->laz_chunk,
                  "LAZ output: points a chunk (default 50000, LASzip's)")
      ->check(CLI::Range(std::uint32_t(1), std::uint32_t(100'000'000)));
  sub->add_flag("--ascii", args->ascii, "PLY output: ascii instead of binary little endian");
  sub->add_flag("-q,--quiet", args->quiet, "No progress or report on stderr");
  command.subcommand = sub;
  command.run = [args] { return runConvert(*args); };
  return command;
}

}  // namespace parallax::cli
