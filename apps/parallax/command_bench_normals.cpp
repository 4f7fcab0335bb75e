// `parallax bench normals FILE [-k 16] [--peer 'COMMAND'] [--repeat N] [--memory MB] [--json]`:
// the time of `parallax process FILE -o OUT.ply --normals K` (read, spill, tiles, normals, write:
// runProcess as the command runs it) beside a peer doing the same to the same file in the same
// run (bench/normals_open3d.py: Open3D's read_point_cloud, estimate_normals(KNN(K)),
// write_point_cloud).
//
// Rounds alternate who goes first, so that drift in a shared machine's load hits both alike.
// Printed, medians over the rounds: wall and CPU time (user + system; the peer's from its
// process, start included), peak memory (Parallax's ru_maxrss; the peer's as it reports it,
// "peak_kb"), the ratios peer / Parallax, and how far apart the two outputs' normals are
// (unsigned angle, the share within 0.5 degree and the largest; the times compare only if the
// results agree). With --json, one JSON object instead. The load average before and after.
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_peer.h"
#include "bench_timing.h"
#include "commands.h"
#include "io/point_file.h"
#include "process/process_runner.h"

namespace parallax::cli {
namespace {

struct BenchNormalsOptions {
  std::string file, peer;
  std::uint32_t k = 16;
  int repeat = 3;
  std::uint64_t memory_mb = 2048;
  bool json = false;
};

// The unsigned angles between two clouds' normals, point by point (the same points in the same
// order: both sides keep the input's).
struct NormalsAgreement {
  double within_half_degree = 0.0;  // share of the points, 0 to 1
  double max_degrees = 0.0;
};

NormalsAgreement compareNormals(const std::filesystem::path& ours,
                                const std::filesystem::path& theirs) {
  const PointCloud a = readPointFile(ours);
  const PointCloud b = readPointFile(theirs);
  if (a.count != b.count || !a.hasNormals() || !b.hasNormals()) {
    throw std::runtime_error("bench normals: " + theirs.string() + " holds " +
                             std::to_string(b.count) + " points" +
                             (b.hasNormals() ? "" : " without normals") + ", " + ours.string() +
                             " " + std::to_string(a.count) + ": the peer did not do the same work");
  }
  NormalsAgreement agreement;
  std::uint64_t within = 0;
  for (std::size_t i = 0; i < a.count; ++i) {
    const Float3 n = a.normals[i], m = b.normals[i];
    const double dot = double(n.x) * m.x + double(n.y) * m.y + double(n.z) * m.z;
    const double norms = std::sqrt((double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z) *
                                   (double(m.x) * m.x + double(m.y) * m.y + double(m.z) * m.z));
    // A point without a normal (fewer than three neighbours) on either side is 90 degrees off.
    const double degrees =
        norms > 0.0 ? std::acos(std::min(1.0, std::abs(dot) / norms)) * 180.0 / M_PI : 90.0;
    agreement.max_degrees = std::max(agreement.max_degrees, degrees);
    within += degrees <= 0.5;
  }
  agreement.within_half_degree = a.count ? double(within) / double(a.count) : 1.0;
  return agreement;
}

struct Runs {
  std::vector<double> wall, cpu, peak_mb;
};

int runBenchNormals(const BenchNormalsOptions& options) {
  const std::vector<double> load_before = loadAverage();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("parallax-bench-normals-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  struct RemoveDir {
    std::filesystem::path dir;
    ~RemoveDir() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } remove_dir{dir};
  const std::filesystem::path ours_path = dir / "parallax.ply", theirs_path = dir / "peer.ply";

  ProcessOptions process;
  process.inputs.push_back({options.file, {}});
  process.output = ours_path;
  process.steps.push_back(NormalsStep{.k = options.k});
  process.memory_mb = options.memory_mb;
  const std::string peer_command =
      peerCommandLine(options.peer, {{"{file}", shellQuoted(options.file)},
                                     {"{k}", std::to_string(options.k)},
                                     {"{output}", shellQuoted(theirs_path.string())}});

  Runs ours, theirs;
  ProcessReport report;
  auto runOurs = [&] {
    const auto start = Clock::now();
    const double cpu_start = rusageCpuSeconds(RUSAGE_SELF);
    report = runProcess(process);
    ours.wall.push_back(secondsSince(start));
    ours.cpu.push_back(rusageCpuSeconds(RUSAGE_SELF) - cpu_start);
    ours.peak_mb.push_back(peakResidentMegabytes());  // the process's: nothing else here is large
  };
  auto runTheirs = [&] {
    const PeerRun run = runPeer(peer_command, "bench normals --peer");
    theirs.wall.push_back(run.wall);
    theirs.cpu.push_back(run.cpu);
    theirs.peak_mb.push_back(
        peerPeakMegabytes(peerJson(run, peer_command, "bench normals --peer")));
  };
  for (int round = 0; round < options.repeat; ++round) {
    if (options.peer.empty() || round % 2 == 0) {
      runOurs();
      if (!options.peer.empty()) runTheirs();
    } else {
      runTheirs();
      runOurs();
    }
  }
  std::optional<NormalsAgreement> agreement;
  if (!options.peer.empty()) agreement = compareNormals(ours_path, theirs_path);
  const std::vector<double> load_after = loadAverage();

  if (options.json) {
    nlohmann::json result = {{"file", options.file},
                             {"points", report.input_points},
                             {"k", options.k},
                             {"tiles", report.tiles},
                             {"rounds", options.repeat},
                             {"load_average_before", load_before},
                             {"load_average_after", load_after},
                             {"parallax",
                              {{"wall_s", median(ours.wall)},
                               {"cpu_s", median(ours.cpu)},
                               {"peak_mb", median(ours.peak_mb)},
                               {"wall_each_s", ours.wall},
                               {"cpu_each_s", ours.cpu}}}};
    if (agreement) {
      result["peer"] = {{"command", peer_command},
                        {"wall_s", median(theirs.wall)},
                        {"cpu_s", median(theirs.cpu)},
                        {"wall_each_s", theirs.wall},
                        {"cpu_each_s", theirs.cpu}};
      const double peak = median(theirs.peak_mb);
      result["peer"]["peak_mb"] = std::isnan(peak) ? nlohmann::json() : nlohmann::json(peak);
      result["ratio"] = {{"wall", median(theirs.wall) / median(ours.wall)},
                         {"cpu", median(theirs.cpu) / median(ours.cpu)}};
      result["normals"] = {{"within_half_degree", agreement->within_half_degree},
                           {"max_degrees", agreement->max_degrees}};
    }
    std::printf("%s\n", result.dump().c_str());
    return 0;
  }
  std::printf(
      "bench normals: %s, %llu points, K = %u, %zu tile(s), median of %d round(s), load average "
      "%.1f %.1f %.1f before\n",
      options.file.c_str(), static_cast<unsigned long long>(report.input_points), options.k,
      report.tiles, options.repeat, load_before[0], load_before[1], load_before[2]);
  std::printf("parallax  wall %.2f s, cpu %.2f s, peak %.0f MB\n", median(ours.wall),
              median(ours.cpu), median(ours.peak_mb));
  if (agreement) {
    const double peak = median(theirs.peak_mb);
    const std::string peak_text =
        std::isnan(peak) ? std::string("not reported") : std::to_string(std::llround(peak)) + " MB";
    std::printf("peer      wall %.2f s, cpu %.2f s, peak %s (%s)\n", median(theirs.wall),
                median(theirs.cpu), peak_text.c_str(), peer_command.c_str());
    std::printf(
        "ratio     peer / parallax: wall %.2f, cpu %.2f; normals %.4f %% within 0.5 degree "
        "(unsigned), at most %.3g degrees apart\n",
        median(theirs.wall) / median(ours.wall), median(theirs.cpu) / median(ours.cpu),
        100.0 * agreement->within_half_degree, agreement->max_degrees);
  }
  std::printf("load average %.1f %.1f %.1f after\n", load_after[0], load_after[1], load_after[2]);
  return 0;
}

}  // namespace

Command addBenchNormalsCommand(CLI::App& bench) {
  auto options = std::make_shared<BenchNormalsOptions>();
  Command command;
  command.subcommand = bench.add_subcommand(
      "normals",
      "Time `process FILE --normals K` (read, normals, PLY written) beside a peer doing the same "
      "to the same file (bench/normals_open3d.py)");
  command.subcommand->add_option("file", options->file, "Point file")->required();
  command.subcommand->add_option("-k", options->k, "Nearest neighbours of a normal")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  command.subcommand
      ->add_option("--repeat,-n", options->repeat, "Rounds, alternating who goes first (medians)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command.subcommand->add_option("--memory", options->memory_mb, "process's --memory (MB)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command.subcommand->add_option(
      "--peer", options->peer,
      "A command writing FILE's points with their K-nearest normals to {output} (PLY) and printing "
      "a JSON line last (\"peak_kb\"); {file}, {k} and {output} are replaced (e.g. 'python3 "
      "bench/normals_open3d.py {file} {k} {output}')");
  command.subcommand->add_flag("--json", options->json, "One JSON object instead of the lines");
  command.run = [options] { return runBenchNormals(*options); };
  return command;
}

}  // namespace parallax::cli
