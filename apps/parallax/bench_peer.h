// A peer program a benchmark times beside Parallax in the same run (`bench load`, `bench laz`,
// `bench register`, `bench normals`): its command line with placeholders replaced by quoted
// file names, run through /bin/sh, its wall and CPU time (user + system of the finished child,
// its shell and start included), its standard output, and the JSON line a peer script prints
// last. One copy for every bench mode: each had its own quoting, running and parsing before.
#pragma once

#include <sys/resource.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench_timing.h"

namespace parallax::cli {

// `text` single-quoted for /bin/sh (a quote inside becomes '\'').
inline std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// `pattern` with every occurrence of each placeholder replaced by its value, as given (quote
// file names with shellQuoted first; numbers need no quotes).
inline std::string peerCommandLine(
    std::string pattern, const std::vector<std::pair<std::string, std::string>>& replacements) {
  for (const auto& [from, to] : replacements) {
    for (std::size_t at = 0; (at = pattern.find(from, at)) != std::string::npos; at += to.size()) {
      pattern.replace(at, from.size(), to);
    }
  }
  return pattern;
}

struct PeerRun {
  double wall = 0.0;   // seconds, its process start included
  double cpu = 0.0;    // user + system seconds of the child (RUSAGE_CHILDREN's growth)
  std::string output;  // what it printed on standard output
};

// Runs `command` through /bin/sh and waits for it. A failure (cannot start, nonzero exit) throws
// std::runtime_error naming `who` (e.g. "bench register --peer") and the command.
inline PeerRun runPeer(const std::string& command, const std::string& who) {
  PeerRun run;
  const auto start = Clock::now();
  const double cpu_start = rusageCpuSeconds(RUSAGE_CHILDREN);
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error(who + ": cannot run '" + command + "'");
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), int(buffer.size()), pipe)) run.output += buffer.data();
  const int status = pclose(pipe);
  run.wall = secondsSince(start);
  run.cpu = rusageCpuSeconds(RUSAGE_CHILDREN) - cpu_start;
  if (status != 0) {
    throw std::runtime_error(who + ": '" + command + "' failed (status " + std::to_string(status) +
                             ")");
  }
  return run;
}

// The last line of a peer's output parsed as JSON, or std::runtime_error naming `who` and the
// command.
inline nlohmann::json peerJson(const PeerRun& run, const std::string& command,
                               const std::string& who) {
  const std::string& out = run.output;
  const std::size_t line = out.find_last_of('\n', out.size() >= 2 ? out.size() - 2 : 0);
  try {
    return nlohmann::json::parse(line == std::string::npos ? out : out.substr(line + 1));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(who + ": the last line of '" + command + "' is not JSON (" + e.what() +
                             ")");
  }
}

// The peer's peak resident memory in MB as it reports it ("peak_kb", its /proc/self/status
// VmHWM), or NaN. getrusage's figure for a child would include this process's own peak: Linux
// keeps ru_maxrss across the fork and exec.
inline double peerPeakMegabytes(const nlohmann::json& reported) {
  if (reported.contains("peak_kb") && reported["peak_kb"].is_number()) {
    return double(reported["peak_kb"]) / 1024.0;
  }
  return std::nan("");
}

}  // namespace parallax::cli
