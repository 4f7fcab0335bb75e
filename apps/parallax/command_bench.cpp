// `parallax bench MODE ...`: speed measurements with a same-run reference beside each number.
//
// Modes are sub-subcommands, each one function that registers its options on the `bench` app and
// returns a Command (commands.h); `bench` runs whichever was chosen. Add one by writing
// `Command addBench<Mode>Command(CLI::App& bench)` (in its own command_bench_<mode>.cpp for
// anything large, declared in commands.h) and listing it in addBenchCommand below.
//
// bench load FILE [--repeat N]
//   Loads FILE N times (default 5) with readPointFile, the path every command uses (any format:
//   binary PLY and binary PCD are compared this way), and reports the median and best time, MB/s
//   and M points/s. The reference, measured in the same run and
//   interleaved with the loads: open + read() of the whole file into a newly allocated buffer,
//   which is the least any loader must do (the kernel copy and the first touch of fresh memory).
//   That is numpy.fromfile's work: the buffer is advised into huge pages as numpy's large arrays
//   and the columns are. Every timed action starts on memory just freed (touchAndFreeMemory): on
//   these virtual machines memory freed for about 2 s goes back to the host and its next first
//   touch costs about 4 ms a MB, which would otherwise be charged to whichever action came first
//   after a pause.
//   "load / reference" says how much the parsing costs on top. One warm-up read comes first so
//   that both measure from the page cache, never from the disk. Peak memory (ru_maxrss) is shown
//   beside the size of the columns the load produced, and the CPU time of a load (user + system),
//   a per-core figure that holds on a shared machine. --threads N limits the load's threads.
//   --peer 'COMMAND' also times another program reading the same file (a reference library's
//   reader built beside the project, e.g. libE57Format's for E57), run through /bin/sh with "{}"
//   replaced by the file, interleaved with the loads; "peer / load" is the speed-up. Its time
//   includes its process start, so give it a file that takes seconds.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_peer.h"
#include "bench_timing.h"
#include "commands.h"
#include "core/attribute_selection.h"
#include "core/error.h"
#include "core/point_cloud.h"
#include "io/point_file.h"
#include "progress_options.h"
#include "xr_view.h"

namespace parallax::cli {
namespace {

[[noreturn]] void throwReadError(const std::string& path, int error) {
  throw InputError({.file = path, .expected = "a readable file", .found = std::strerror(error)});
}

// The reference: the whole file into a fresh, untouched buffer with read(2), allocated as the
// columns are (core/column.h: large ones mapped and advised into huge pages, as numpy does for
// the array numpy.fromfile fills). Returns the bytes read; the buffer is freed after the clock
// stops (as the loaded cloud is).
std::uint64_t readIntoNewBuffer(const std::string& path, ByteBuffer& buffer) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwReadError(path, errno);
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    const int error = errno;
    ::close(fd);
    throwReadError(path, error);
  }
  const std::size_t size = std::size_t(info.st_size);
  buffer = ByteBuffer(size);  // not touched before read() fills it
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::read(fd, buffer.data() + done, size - done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      const int error = got < 0 ? errno : EIO;
      ::close(fd);
      throwReadError(path, error);
    }
    done += std::size_t(got);
  }
  ::close(fd);
  return done;
}

std::uint64_t columnBytes(const PointCloud& cloud) {
  std::uint64_t bytes = cloud.positions.size() * sizeof(Int3) +
                        cloud.colors.size() * sizeof(Rgba8) +
                        cloud.normals.size() * sizeof(Float3) + cloud.intensity.size() * 4 +
                        cloud.classification.size();
  for (const auto& column : cloud.scalars) bytes += column.data.size();
  return bytes;
}

struct Times {
  std::vector<double> seconds;
  double median() const {
    std::vector<double> sorted = seconds;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }
  double best() const { return *std::min_element(seconds.begin(), seconds.end()); }
};

struct LoadOptions {
  std::string file;
  int repeat = 5;
  int threads = 0;     // 0: every core
  bool quiet = false;  // no progress bar (the figures are the result: printed)
  std::string peer;    // a command line timed beside the loads ("{}": the file); empty: none
  // Only these attributes (as `render` asks for what it draws); a full load is then timed beside
  // each as the reference. Empty: every attribute, no second load.
  std::vector<std::string> attributes;
};

int runBenchLoad(const LoadOptions& options) {
  const std::string& path = options.file;
  // Warm-up: puts the file in the page cache ("drop nothing": both measurements then read memory).
  ByteBuffer buffer;
  const std::uint64_t file_bytes = readIntoNewBuffer(path, buffer);
  buffer = ByteBuffer();
  // More than a load's columns (at most about twice the file for every format read whole).
  const std::size_t fresh_bytes = std::size_t(2 * file_bytes);

  std::optional<tbb::global_control> limit;
  if (options.threads > 0) {
    limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(options.threads));
  }
  Times load, reference, reference_cpu, load_cpu, peer, peer_cpu, full, full_cpu;
  const AttributeSelection selection = options.attributes.empty()
                                           ? AttributeSelection{}
                                           : AttributeSelection::only(options.attributes);
  std::uint64_t points = 0, columns = 0;
  // Advanced between the timed parts only, so that drawing it is never inside a measurement.
  auto progress = progressBar(options.quiet, "bench load", std::uint64_t(options.repeat), "loads");
  for (int i = 0; i < options.repeat; ++i) {
    // Interleaved, so that drift in the machine's load (shared cores) hits both alike.
    touchAndFreeMemory(fresh_bytes);
    auto start = Clock::now();
    const double reference_start = rusageCpuSeconds(RUSAGE_SELF);
    readIntoNewBuffer(path, buffer);
    reference.seconds.push_back(secondsSince(start));
    reference_cpu.seconds.push_back(rusageCpuSeconds(RUSAGE_SELF) - reference_start);
    buffer = ByteBuffer();

    touchAndFreeMemory(fresh_bytes);
    start = Clock::now();
    const double cpu_start = rusageCpuSeconds(RUSAGE_SELF);
    PointCloud cloud = readPointFile(path, {.attributes = selection});
    load.seconds.push_back(secondsSince(start));
    load_cpu.seconds.push_back(rusageCpuSeconds(RUSAGE_SELF) - cpu_start);
    points = cloud.count;
    columns = columnBytes(cloud);
    cloud = PointCloud();
    if (!selection.all()) {
      touchAndFreeMemory(fresh_bytes);
      start = Clock::now();
      const double full_start = rusageCpuSeconds(RUSAGE_SELF);
      cloud = readPointFile(path);
      full.seconds.push_back(secondsSince(start));
      full_cpu.seconds.push_back(rusageCpuSeconds(RUSAGE_SELF) - full_start);
      cloud = PointCloud();
    }
    if (!options.peer.empty()) {
      touchAndFreeMemory(fresh_bytes);
      const PeerRun run =
          runPeer(peerCommandLine(options.peer, {{"{}", shellQuoted(path)}}), "bench load --peer");
      peer.seconds.push_back(run.wall);
      peer_cpu.seconds.push_back(run.cpu);
    }
    if (progress) progress->advance(1);
  }
  progress.reset();  // its last line before the figures

  const double mb = double(file_bytes) / 1e6;
  const double load_median = load.median(), reference_median = reference.median();
  std::printf("file       %s: %.1f MB, %llu points\n", path.c_str(), mb,
              static_cast<unsigned long long>(points));
  std::printf("repeat     %d, after one warm-up read (the file is in the page cache)\n",
              options.repeat);
  std::printf("load       median %.4f s, best %.4f s: %.1f MB/s, %.2f M points/s\n", load_median,
              load.best(), mb / load_median, double(points) / load_median / 1e6);
  std::printf(
      "reference  median %.4f s, best %.4f s: %.1f MB/s, %.4f s of CPU (open + read() into a "
      "new buffer)\n",
      reference_median, reference.best(), mb / reference_median, reference_cpu.median());
  std::printf(
      "cpu        median %.4f s of CPU a load (user + system, %s): %.2f M points/s per "
      "CPU second\n",
      load_cpu.median(),
      options.threads > 0 ? (std::to_string(options.threads) + " threads").c_str() : "all cores",
      double(points) / load_cpu.median() / 1e6);
  std::printf("ratio      load / reference = %.2f (median), %.2f (best), %.2f in CPU time\n",
              load_median / reference_median, load.best() / reference.best(),
              load_cpu.median() / reference_cpu.median());
  if (!full.seconds.empty()) {
    std::string names;
    for (const std::string& name : options.attributes) names += (names.empty() ? "" : ",") + name;
    std::printf(
        "full load  median %.4f s, best %.4f s, %.4f s of CPU; the load above read x,y,z,%s "
        "only: speed-up full / selective = %.2f (median), %.2f (best), %.2f in CPU time\n",
        full.median(), full.best(), full_cpu.median(), names.c_str(), full.median() / load_median,
        full.best() / load.best(), full_cpu.median() / load_cpu.median());
  }
  if (!peer.seconds.empty()) {
    std::printf("peer       median %.4f s, best %.4f s: %.2f M points/s (%s)\n", peer.median(),
                peer.best(), double(points) / peer.median() / 1e6, options.peer.c_str());
    std::printf(
        "speed-up   peer / load = %.2f (median), %.2f (best); in CPU time %.2f (the peer "
        "%.4f s of CPU a run, median, its shell included)\n",
        peer.median() / load_median, peer.best() / load.best(),
        peer_cpu.median() / load_cpu.median(), peer_cpu.median());
  }
  std::printf("memory     peak RSS %.1f MB; columns %.1f MB; file %.1f MB\n",
              peakResidentMegabytes() * 1.048576, double(columns) / 1e6, mb);
  return 0;
}

Command addBenchLoadCommand(CLI::App& bench) {
  auto options = std::make_shared<LoadOptions>();
  Command command;
  command.subcommand = bench.add_subcommand(
      "load", "Time loading a file against reading its bytes into a new buffer");
  command.subcommand->add_option("file", options->file, "Point file")->required();
  command.subcommand
      ->add_option("--repeat,-n", options->repeat, "Loads to time (median and best are shown)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command.subcommand
      ->add_option("--threads", options->threads,
                   "Threads the load may use (default 0: every core; 1 gives a per-core figure)")
      ->check(CLI::Range(0, 1024));
  command.subcommand->add_option(
      "--peer", options->peer,
      "A command reading the same file, timed beside each load (\"{}\" is replaced by the file; "
      "run through /bin/sh)");
  command.subcommand
      ->add_option(
          "--attributes", options->attributes,
          "Load only these attributes (comma list of info's names: red, intensity, gps_time, ...; "
          "positions always), as render asks for what it draws; a full load is timed beside each")
      ->delimiter(',');
  addQuietFlag(*command.subcommand, options->quiet);
  command.run = [options] { return runBenchLoad(*options); };
  return command;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
  Command command;
  command.subcommand =
      app.add_subcommand("bench", "Measure speed beside a same-run reference (bench load FILE)");
  command.subcommand->require_subcommand(1);
  // Every mode of `bench`; `bench render` joins this list.
  auto modes = std::make_shared<std::vector<Command>>(std::vector<Command>{
      addBenchLoadCommand(*command.subcommand),
      addBenchRenderCommand(*command.subcommand),
      addBenchConvertCommand(*command.subcommand),
      addBenchLazCommand(*command.subcommand),
      addBenchRegisterCommand(*command.subcommand),
      addBenchNormalsCommand(*command.subcommand),
      addBenchXrCommand(*command.subcommand),
  });
  command.run = [modes] {
    for (const auto& mode : *modes) {
      if (mode.subcommand->parsed()) return mode.run();
    }
    return 1;
  };
  return command;
}

}  // namespace parallax::cli
