// `parallax bench laz FILE`: the speed of the LAZ codec alone (chunks decoded into raw records,
// no columns), beside a same-run reference.
//
// Each round, interleaved so that drift in a shared machine's load hits all alike: the decode
// through the specialised chunk loops (laz/chunk_codec.h, DecoderPath), through the general loop,
// of positions and colour only (layered files: the other layers skipped), and, with --peer, another
// program reading the same file (LASzip's laszip_read_point loop, built beside the project),
// run through /bin/sh with "{}" replaced by the file. --threads 1 (the default) gives per-core
// figures: CPU seconds (user + system) of each, the peer's from its process (start included).
// --threads N decodes the chunks on N threads and compares wall times, the peer on one core.
// The machine's load average is printed with the figures.
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_peer.h"
#include "bench_timing.h"
#include "commands.h"
#include "io/laz_decode.h"

namespace parallax::cli {
namespace {

struct BenchLazOptions {
  std::string file;
  int repeat = 5;
  int threads = 1;
  std::string peer;
};

// The mean of the two middle values for an even count (bench_timing.h's median takes the upper).
double meanMedian(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Series {
  const char* name;
  std::vector<double> wall, cpu;
};

int runBenchLaz(const BenchLazOptions& options) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  std::size_t(options.threads));
  const bool parallel = options.threads > 1;
  const LazDecodeOptions specialised{.parallel = parallel};
  const LazDecodeOptions general{.path = laz::DecoderPath::kGeneral, .parallel = parallel};
  const LazDecodeOptions selective{.fields = laz::fields::kRgb, .parallel = parallel};
  const std::string peer_command =
      peerCommandLine(options.peer, {{"{}", shellQuoted(options.file)}});

  const double load_before = loadAverage()[0];
  // Warm-up: the file into the page cache, and the checksums every path must agree on.
  const LazDecodeResult reference = decodeLazRecords(options.file, specialised);
  if (decodeLazRecords(options.file, general).checksum != reference.checksum) {
    throw std::runtime_error("bench laz: the general and the specialised decode disagree");
  }
  Series runs[] = {
      {"specialised", {}, {}}, {"general", {}, {}}, {"positions+colour", {}, {}}, {"peer", {}, {}}};
  const LazDecodeOptions* paths[] = {&specialised, &general, &selective};
  for (int round = 0; round < options.repeat; ++round) {
    for (int k = 0; k < 3; ++k) {
      const auto start = Clock::now();
      const double cpu = rusageCpuSeconds(RUSAGE_SELF);
      const LazDecodeResult r = decodeLazRecords(options.file, *paths[k]);
      runs[k].cpu.push_back(rusageCpuSeconds(RUSAGE_SELF) - cpu);
      runs[k].wall.push_back(std::chrono::duration<double>(Clock::now() - start).count());
      if (r.checksum != reference.checksum) {
        throw std::runtime_error(std::string("bench laz: the ") + runs[k].name +
                                 " decode gave other positions");
      }
    }
    if (!peer_command.empty()) {
      const PeerRun run = runPeer(peer_command, "bench laz --peer");
      runs[3].cpu.push_back(run.cpu);
      runs[3].wall.push_back(run.wall);
    }
  }

  const double points = double(reference.points);
  std::printf(
      "bench laz: %s, %llu points, %d thread(s), median of %d rounds, load average %.1f "
      "before, %.1f after\n",
      options.file.c_str(), static_cast<unsigned long long>(reference.points), options.threads,
      options.repeat, load_before, loadAverage()[0]);
  for (const Series& s : runs) {
    if (s.cpu.empty()) continue;
    std::printf("%-17s wall %.3f s (%.2f M points/s), cpu %.3f s (%.2f M points/s per CPU s)\n",
                s.name, meanMedian(s.wall), points / meanMedian(s.wall) / 1e6, meanMedian(s.cpu),
                points / meanMedian(s.cpu) / 1e6);
  }
  const double special_cpu = meanMedian(runs[0].cpu), special_wall = meanMedian(runs[0].wall);
  std::printf(
      "ratio             general / specialised cpu %.2f; full / positions+colour cpu "
      "%.2f (the speed-up of decoding only x, y, z and colour)\n",
      meanMedian(runs[1].cpu) / special_cpu, special_cpu / meanMedian(runs[2].cpu));
  if (!runs[3].cpu.empty()) {
    std::printf(
        "speed-up          over the peer: cpu %.2f (per core), wall %.2f (%d thread(s) "
        "against the peer's one)\n",
        meanMedian(runs[3].cpu) / special_cpu, meanMedian(runs[3].wall) / special_wall,
        options.threads);
  }
  return 0;
}

}  // namespace

Command addBenchLazCommand(CLI::App& bench) {
  auto options = std::make_shared<BenchLazOptions>();
  Command command;
  command.subcommand = bench.add_subcommand(
      "laz",
      "Time the LAZ codec (records, no columns): specialised, general and selective "
      "decoding, beside a peer reading the same file");
  command.subcommand->add_option("file", options->file, "LAZ file")->required();
  command.subcommand->add_option("--repeat,-n", options->repeat, "Rounds (medians are shown)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command.subcommand
      ->add_option("--threads", options->threads,
                   "Threads decoding chunks (1: per-core figures in CPU time)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  command.subcommand->add_option(
      "--peer", options->peer,
      "A command reading the same file, timed each round (\"{}\" is replaced by the file)");
  command.run = [options] { return runBenchLaz(*options); };
  return command;
}

}  // namespace parallax::cli
