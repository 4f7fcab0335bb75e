// Runs the built `parallax` executable (PARALLAX_EXECUTABLE, defined by the test target) with its
// standard output and error captured in files of the test's folder: the command-line tests check
// exit codes and messages as a user sees them.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {

struct RunResult {
  int exit_code = -1;  // 128 + signal when the process was killed
  std::string out;
  std::string err;
};

// `text` in single quotes for /bin/sh.
inline std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

inline std::string readText(const std::filesystem::path& path) {
  return fileBytes(path);
}

// Runs a shell command line (a `parallax` command with its redirections) and returns its exit
// code. In sanitizer builds the child would report Mesa's own allocations at exit (llvmpipe's,
// outside this project) as leaks: leak checking is off for the child only.
inline int runWithoutLeakCheck(const std::string& command) {
  const std::string quiet_mesa =
      "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" " + command;
  const int status = std::system(quiet_mesa.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `parallax ARGS` (ARGS as the shell reads them: quote paths with quoted()).
inline RunResult runParallax(const TempDir& dir, const std::string& args) {
  const auto out = dir / "stdout.txt";
  const auto err = dir / "stderr.txt";
  const std::string command = quoted(PARALLAX_EXECUTABLE) + " " + args + " >" +
                              quoted(out.string()) + " 2>" + quoted(err.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = readText(out);
  result.err = readText(err);
  return result;
}

}  // namespace parallax::test
