// `parallax convert IN -o OUT`: converts between any two supported point formats (PLY, LAS,
// text), keeping every attribute the target can hold and saying which ones it drops.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "core/progress.h"
#include "io/las_header.h"
#include "io/las_writer.h"
#include "io/point_file.h"

namespace parallax::cli {
namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  std::vector<std::string> columns;
  std::string las_version;
  bool ascii = false;
  bool quiet = false;
};

int runConvert(const ConvertArgs& args) {
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
      "convert", "Convert a point file between PLY, LAS and text (xyz, txt, csv, pts)");
  sub->add_option("input", args->input, "Input point file (format detected from its content)")
      ->required();
  sub->add_option("-o,--output", args->output,
                  "Output file; its extension picks the format: .ply .las .xyz .txt .csv .asc .pts")
      ->required();
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
