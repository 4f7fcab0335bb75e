// `parallax bench convert FILE...`: the speed of building a Potree 2.0 octree, beside a same-run
// reference.
//
// The conversion runs first (into a temporary directory beside --work, removed afterwards) and
// reports points/s overall and per core, the time of each stage, and the peak resident memory
// (ru_maxrss, taken before the reference runs) against the --memory budget. The reference, timed
// right after: one streaming pass over the same inputs with the same batch reader the
// conversion uses (PointStream), which is the least any pass must cost; the conversion makes
// three such passes plus the build. The CPU time (getrusage) gives the work per core however
// loaded the machine is: points per CPU-second. The machine's load average is printed beside the
// figures, since these machines are shared.
//
// With --twin (the same points in another file: the LAS of a LAZ) and --potree-converter (the
// peer's executable, run on the same inputs), the conversion, its twin's and the peer's are timed
// in turn, --rounds times, and each round prints their ratios: what a slow input costs beside
// its cheaply reread twin, and beside PotreeConverter 2. --keep-all keeps the decoded points of
// every input, so that rereading a LAS can be measured against keeping it.
//
// With --copc the same inputs are then converted to a COPC file (lod/copc_converter.h: the same
// build, then every node encoded as a LAZ chunk) and its throughput is given as a ratio of the
// Potree conversion's, measured in the same run.
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tbb/info.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "commands.h"
#include "lod/copc_converter.h"
#include "lod/potree_converter.h"
#include "progress_options.h"

namespace parallax::cli {
namespace {

struct BenchConvertOptions {
  std::vector<std::string> files;
  std::string sampling = "poisson";
  std::uint64_t memory_mb = 2048;
  int threads = 0;
  std::string work = "";
  bool quiet = false;  // no stage bars (the figures are the result: printed)
  bool copc = false;
  std::vector<std::string> twin;  // the same points in other files (the LAS of a LAZ)
  std::string potree_converter;   // PotreeConverter 2's executable; empty: not run
  int rounds = 1;                 // of the comparison with --twin / --potree-converter
  bool keep_all = false;          // OctreeBuildOptions::keep_all_decoded
};

extern "C" char** environ;

// Runs PotreeConverter 2 on `files` into `output` (its output quietened), waits for it, and
// returns its wall seconds; throws when it fails.
double runPotreeConverter(const std::string& executable, const std::vector<std::string>& files,
                          const std::filesystem::path& output) {
  std::vector<std::string> args{executable};
  args.insert(args.end(), files.begin(), files.end());
  args.push_back("-o");
  args.push_back(output.string());
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int spawned =
      posix_spawn(&pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) throw std::runtime_error(executable + ": cannot run");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(executable + ": lost");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(executable + ": failed (status " + std::to_string(status) + ")");
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runBenchConvert(const BenchConvertOptions& args) {
  std::vector<ConvertInput> inputs, twin;
  for (const std::string& file : args.files) inputs.push_back({file, {}});
  for (const std::string& file : args.twin) twin.push_back({file, {}});
  PotreeConvertOptions options;
  options.build.keep_all_decoded = args.keep_all;
  parseSamplingMethod(args.sampling, options.build.sampling);
  options.build.memory_bytes = args.memory_mb << 20;
  options.build.threads = args.threads;
  options.progress = stageBars(args.quiet);
  const int cores = args.threads > 0 ? args.threads : tbb::info::default_concurrency();
  const std::filesystem::path work =
      args.work.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(args.work);
  const auto output = work / ("parallax-bench-convert-" + std::to_string(::getpid()));

  std::printf(
      "bench convert: %zu input(s), sampling %s, --memory %llu MB, %d threads, "
      "load average %.2f\n",
      inputs.size(), args.sampling.c_str(), static_cast<unsigned long long>(args.memory_mb), cores,
      loadAverage()[0]);
  const double cpu_before = rusageCpuSeconds(RUSAGE_SELF);
  const PotreeConvertResult result = convertToPotree(inputs, output, options);
  const double cpu = rusageCpuSeconds(RUSAGE_SELF) - cpu_before;
  const double peak_mb = peakResidentMegabytes();
  std::filesystem::remove_all(output);
  const double rate = double(result.points) / result.seconds_total;
  std::printf("convert   %llu points in %.2f s: %.2f M points/s, %.2f M points/s per core\n",
              static_cast<unsigned long long>(result.points), result.seconds_total, rate / 1e6,
              rate / 1e6 / cores);
  std::printf(
      "  cpu     %.2f s user+system: %.2f M points per CPU-second (%.0f%% of %d cores busy)\n", cpu,
      double(result.points) / cpu / 1e6, 100.0 * cpu / result.seconds_total / cores, cores);
  std::printf("  stages  scan %.2f s, count %.2f s, distribute %.2f s, build %.2f s\n",
              result.seconds_scan, result.seconds_count, result.seconds_distribute,
              result.seconds_build);
  std::printf("  octree  %zu nodes, depth %d, %zu chunks, %.1f MB octree.bin\n", result.nodes,
              result.depth, result.chunks, double(result.octree_bytes) / 1e6);
  std::printf("  memory  peak resident %.0f MB (budget %llu MB)\n", peak_mb,
              static_cast<unsigned long long>(args.memory_mb));
  std::printf(
      "  kept    %llu decoded points for the later passes: %.0f MB in memory, %.0f MB "
      "in scratch files\n",
      static_cast<unsigned long long>(result.kept_points), double(result.kept_memory_bytes) / 1e6,
      double(result.kept_file_bytes) / 1e6);

  // Reference: one streaming read of the inputs in the conversion's batches.
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t read = 0;
  for (const ConvertInput& input : inputs) {
    PointStream stream(input.path, input.text_columns);
    PointCloud batch;
    while (stream.next(batch, 1u << 20)) read += batch.count;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("reference one streaming read: %.2f s, %.2f M points/s (convert = %.1f reads)\n",
              seconds, double(read) / seconds / 1e6, result.seconds_total / seconds);
  if (!twin.empty() || !args.potree_converter.empty()) {
    options.progress = nullptr;
    for (int round = 1; round <= args.rounds; ++round) {
      const double load = loadAverage()[0];
      const double convert = convertToPotree(inputs, output, options).seconds_total;
      std::filesystem::remove_all(output);
      std::printf("round %d (load average %.2f): convert %.2f s", round, load, convert);
      if (!twin.empty()) {
        // The twin as a plain conversion reads it (--keep-all is for the inputs).
        PotreeConvertOptions twin_options = options;
        twin_options.build.keep_all_decoded = false;
        const double twin_seconds = convertToPotree(twin, output, twin_options).seconds_total;
        std::filesystem::remove_all(output);
        std::printf(", twin %.2f s, convert / twin %.2f", twin_seconds, convert / twin_seconds);
      }
      if (!args.potree_converter.empty()) {
        const double peer = runPotreeConverter(args.potree_converter, args.files, output);
        std::filesystem::remove_all(output);
        std::printf(", PotreeConverter %.2f s, PotreeConverter / convert %.2f", peer,
                    peer / convert);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  if (args.copc) {
    const auto copc_output =
        work / ("parallax-bench-convert-" + std::to_string(::getpid()) + ".copc.laz");
    CopcConvertOptions copc_options;
    copc_options.potree = options;
    const double copc_cpu_before = rusageCpuSeconds(RUSAGE_SELF);
    const CopcConvertResult copc = convertToCopc(inputs, copc_output, copc_options);
    const double copc_cpu = rusageCpuSeconds(RUSAGE_SELF) - copc_cpu_before;
    const double bytes = double(std::filesystem::file_size(copc_output));
    std::filesystem::remove(copc_output);
    const double copc_rate = double(copc.copc.points) / copc.seconds_total;
    std::printf(
        "copc      %llu points in %.2f s: %.2f M points/s (build %.2f s, COPC %.2f s), "
        "%.2f M points per CPU-second; %.1f MB (%.1f bytes a point)\n",
        static_cast<unsigned long long>(copc.copc.points), copc.seconds_total, copc_rate / 1e6,
        copc.build.seconds_total, copc.seconds_write, double(copc.copc.points) / copc_cpu / 1e6,
        bytes / 1e6, bytes / double(std::max<std::uint64_t>(1, copc.copc.points)));
    std::printf("  ratio   COPC / Potree throughput %.2f wall, %.2f per CPU-second\n",
                copc_rate / rate,
                (double(copc.copc.points) / copc_cpu) / (double(result.points) / cpu));
  }
  std::printf("load average after: %.2f\n", loadAverage()[0]);
  return 0;
}

}  // namespace

Command addBenchConvertCommand(CLI::App& bench) {
  auto options = std::make_shared<BenchConvertOptions>();
  Command command;
  command.subcommand = bench.add_subcommand(
      "convert", "Time the Potree 2.0 conversion against one streaming read of the input");
  command.subcommand->add_option("files", options->files, "Point files")->required();
  command.subcommand->add_option("--sampling", options->sampling, "poisson or random")
      ->check(CLI::IsMember({"poisson", "random"}))
      ->capture_default_str();
  command.subcommand->add_option("--memory", options->memory_mb, "Memory budget in MB")
      ->capture_default_str();
  command.subcommand->add_option("--threads", options->threads, "Threads (0: all cores)");
  command.subcommand->add_option("--work", options->work,
                                 "Folder for the temporary output (default: the temp folder)");
  addQuietFlag(*command.subcommand, options->quiet);
  command.subcommand->add_flag("--copc", options->copc,
                               "Also convert to COPC and compare its throughput with Potree's");
  command.subcommand->add_option(
      "--twin", options->twin,
      "The same points in other files (the LAS of a LAZ): converted in turn, with ratios");
  command.subcommand->add_option("--potree-converter", options->potree_converter,
                                 "PotreeConverter 2's executable: run on the same inputs in turn");
  command.subcommand
      ->add_option("--rounds", options->rounds,
                   "Rounds of the comparison with --twin / --potree-converter")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command.subcommand->add_flag("--keep-all", options->keep_all,
                               "Keep the decoded points of every input, also those that reread "
                               "cheaply (LAS, binary PLY)");
  command.run = [options] { return runBenchConvert(*options); };
  return command;
}

}  // namespace parallax::cli
