// `parallax bench register SOURCE TARGET [--max-distance D] [--peer 'COMMAND']`: the time and the
// result of point-to-plane ICP (what `parallax register` runs: read both files, the target's
// normals, coarse to fine) beside a peer aligning the same two files in the same run.
//
// The peer (bench/icp_open3d.py: Open3D's registration_icp) runs through /bin/sh with {source},
// {target} and {distance} replaced, after Parallax, and prints one JSON line with its
// "transform" (SOURCE -> TARGET, 4 rows of 4), "rms" and "overlap" (and its "peak_kb"). Printed:
// wall and CPU time (user + system; the peer's from its process, start included), peak memory,
// RMS, overlap, the ratios peer / Parallax, and how far apart the two transforms put the corners
// of the source's bounds (the results must agree for the times to compare). The load average
// before and after.
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "bench_peer.h"
#include "bench_timing.h"
#include "commands.h"
#include "core/bounds.h"
#include "io/point_file.h"
#include "registration/cloud_registration.h"

namespace parallax::cli {
namespace {

struct BenchRegisterOptions {
  std::string source, target, peer;
  double max_distance = 0.0;
};

int runBenchRegister(const BenchRegisterOptions& options) {
  const std::vector<double> load_before = loadAverage();
  IcpOptions icp;
  icp.max_distance = options.max_distance;
  const auto start = Clock::now();
  const double cpu_start = rusageCpuSeconds(RUSAGE_SELF);
  const PointCloud source = readPointFile(options.source);
  const PointCloud target = readPointFile(options.target);
  const IcpResult ours = registerClouds(source, target, icp, options.source, options.target);
  const double wall = secondsSince(start);
  const double cpu = rusageCpuSeconds(RUSAGE_SELF) - cpu_start;
  const double peak = peakResidentMegabytes();
  std::printf(
      "bench register: %s (%llu points) onto %s (%llu points), max distance %.6g, load average "
      "%.1f %.1f %.1f before\n",
      options.source.c_str(), static_cast<unsigned long long>(source.count), options.target.c_str(),
      static_cast<unsigned long long>(target.count), ours.max_distance, load_before[0],
      load_before[1], load_before[2]);
  std::printf(
      "parallax  wall %.2f s, cpu %.2f s, peak %.0f MB, rms %.9g, overlap %.6f, %u iterations\n",
      wall, cpu, peak, ours.rms, ours.overlap, ours.iterations);
  if (!options.peer.empty()) {
    char distance[64];
    std::snprintf(distance, sizeof distance, "%.17g", ours.max_distance);
    const std::string command =
        peerCommandLine(options.peer, {{"{source}", shellQuoted(options.source)},
                                       {"{target}", shellQuoted(options.target)},
                                       {"{distance}", distance}});
    const PeerRun run = runPeer(command, "bench register --peer");
    const double peer_wall = run.wall, peer_cpu = run.cpu;
    const nlohmann::json theirs = peerJson(run, command, "bench register --peer");
    RigidTransform peer_transform;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) peer_transform.m[r][c] = theirs.at("transform").at(r).at(c);
    }
    // How far apart the two transforms put the corners of the source's bounds: the largest
    // disagreement over the source's points is at a corner of their box.
    double apart = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const Point3 p{corner & 1 ? source.bounds.max[0] : source.bounds.min[0],
                     corner & 2 ? source.bounds.max[1] : source.bounds.min[1],
                     corner & 4 ? source.bounds.max[2] : source.bounds.min[2]};
      const Point3 a = ours.transform.apply(p), b = peer_transform.apply(p);
      apart = std::max(apart, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
    const double peer_rms = theirs.at("rms");
    const double peer_peak_mb = peerPeakMegabytes(theirs);
    const std::string peer_peak = std::isnan(peer_peak_mb)
                                      ? std::string("not reported")
                                      : std::to_string(std::llround(peer_peak_mb)) + " MB";
    std::printf("peer      wall %.2f s, cpu %.2f s, peak %s, rms %.9g, overlap %.6f\n", peer_wall,
                peer_cpu, peer_peak.c_str(), peer_rms, double(theirs.at("overlap")));
    std::printf(
        "ratio     peer / parallax: wall %.2f, cpu %.2f; rms differ by %.3g (relative); the two "
        "transforms put the source's corners at most %.3g apart\n",
        peer_wall / wall, peer_cpu / cpu, std::abs(peer_rms - ours.rms) / ours.rms, apart);
  }
  const std::vector<double> load_after = loadAverage();
  std::printf("load average %.1f %.1f %.1f after\n", load_after[0], load_after[1], load_after[2]);
  return 0;
}

}  // namespace

Command addBenchRegisterCommand(CLI::App& bench) {
  auto options = std::make_shared<BenchRegisterOptions>();
  Command command;
  command.subcommand = bench.add_subcommand(
      "register",
      "Time point-to-plane ICP of SOURCE onto TARGET (as `parallax register`) beside a peer "
      "aligning the same files (bench/icp_open3d.py)");
  command.subcommand->add_option("source", options->source, "The cloud to move")->required();
  command.subcommand->add_option("target", options->target, "The cloud it is aligned to")
      ->required();
  command.subcommand
      ->add_option("--max-distance", options->max_distance,
                   "Pairs farther apart are ignored (default: a twentieth of the target's "
                   "bounding box diagonal)")
      ->check(CLI::PositiveNumber);
  command.subcommand->add_option(
      "--peer", options->peer,
      "A command aligning the same files and printing {\"transform\", \"rms\", \"overlap\"} as "
      "its last line; {source}, {target} and {distance} are replaced (e.g. 'python3 "
      "bench/icp_open3d.py {source} {target} {distance}')");
  command.run = [options] { return runBenchRegister(*options); };
  return command;
}

}  // namespace parallax::cli
