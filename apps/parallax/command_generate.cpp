// `parallax generate`: a synthetic scan of any size, streamed to a PLY file.
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "commands.h"
#include "core/progress.h"
#include "progress_options.h"
#include "synth/scene_generator.h"

namespace parallax::cli {

Command addGenerateCommand(CLI::App& app) {
  struct Options {
    std::string output;
    std::uint64_t points = 0;
    std::string scene = "scan";
    std::string format_name = "binary";
    std::uint64_t seed = 1;
    int threads = 0;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  Command command;
  command.subcommand = app.add_subcommand(
      "generate",
      "Write a synthetic point cloud (a simulated laser scan of terrain, buildings and trees) as "
      "PLY: float x y z, float nx ny nz, uchar red green blue");
  auto* sub = command.subcommand;
  sub->add_option("-o,--output", options->output, "PLY file to write")->required();
  sub->add_option("--points", options->points, "number of points (any size: streamed)")
      ->required()
      ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()));
  std::string scene_help = "scene:";
  for (const auto& name : synth::SceneGenerator::sceneNames()) scene_help += " " + name;
  sub->add_option("--scene", options->scene, scene_help)->capture_default_str();
  sub->add_option("--format", options->format_name, "ascii, binary (little endian) or binary-be")
      ->check(CLI::IsMember({"ascii", "binary", "binary-be"}))
      ->capture_default_str();
  sub->add_option("--seed", options->seed, "random seed; the same seed gives the same file")
      ->capture_default_str();
  sub->add_option("--threads", options->threads, "worker threads (0: all cores)")
      ->capture_default_str();
  addQuietFlag(*sub, options->quiet);

  command.run = [options] {
    synth::GenerateOptions generate;
    generate.scene.scene = options->scene;
    generate.scene.seed = options->seed;
    generate.points = options->points;
    const std::map<std::string, PlyFormat> formats = {{"ascii", PlyFormat::Ascii},
                                                      {"binary", PlyFormat::BinaryLittleEndian},
                                                      {"binary-be", PlyFormat::BinaryBigEndian}};
    generate.format = formats.at(options->format_name);
    generate.max_threads = options->threads;
    // Built before the progress bar so that an unknown scene fails before anything is drawn.
    synth::SceneGenerator check(generate.scene);
    synth::GenerateStats stats;
    {
      const auto progress = progressBar(options->quiet, "generate", options->points);
      generate.progress = progress.get();
      stats = synth::generatePly(options->output, generate);
    }
    if (options->quiet) return 0;
    double rate = stats.seconds > 0 ? double(stats.points) / stats.seconds / 1e6 : 0.0;
    std::printf("%s: %llu points, %llu bytes in %.2f s (%.2f M points/s)\n",
                options->output.c_str(), static_cast<unsigned long long>(stats.points),
                static_cast<unsigned long long>(stats.bytes), stats.seconds, rate);
    return 0;
  };
  return command;
}

}  // namespace parallax::cli
