#include "io/partial_output.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <stdexcept>
#include <system_error>

namespace parallax {
namespace {

// The folder and name of a target given as "DIR/NAME" or "DIR/NAME/".
std::filesystem::path normalTarget(const std::filesystem::path& target) {
  std::filesystem::path path = target.lexically_normal();
  if (!path.has_filename()) path = path.parent_path();
  return path;
}

// The pid in "PID" or "PID-N"; 0 when the text is anything else.
pid_t pidOf(std::string_view rest) {
  const std::size_t dash = rest.find('-');
  const std::string_view digits = rest.substr(0, dash);
  if (digits.empty()) return 0;
  if (dash != std::string_view::npos) {
    const std::string_view n = rest.substr(dash + 1);
    if (n.empty() || !std::all_of(n.begin(), n.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return 0;
  }
  long long pid = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
  if (error != std::errc() || end != digits.data() + digits.size() || pid <= 0 ||
      pid > 0x7fffffff) {
    return 0;
  }
  return pid_t(pid);
}

std::uint64_t bytesIn(const std::filesystem::path& path) {
  std::error_code error;
  const auto status = std::filesystem::symlink_status(path, error);
  if (error) return 0;
  if (std::filesystem::is_regular_file(status)) {
    const auto size = std::filesystem::file_size(path, error);
    return error ? 0 : size;
  }
  if (!std::filesystem::is_directory(status)) return 0;
  std::uint64_t bytes = 0;
  for (auto it = std::filesystem::recursive_directory_iterator(
           path, std::filesystem::directory_options::skip_permission_denied, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
    if (it->is_regular_file(error) && !it->is_symlink(error)) {
      const auto size = it->file_size(error);
      if (!error) bytes += size;
    }
    error.clear();
  }
  return bytes;
}

}  // namespace

std::filesystem::path partialOutputPath(const std::filesystem::path& target,
                                        const std::string& suffix) {
  const std::filesystem::path path = normalTarget(target);
  // Built piece by piece: g++ 12 warns (-Wrestrict, falsely) on a chain of string additions.
  std::string name = ".";
  name += path.filename().string();
  name += ".partial-";
  name += std::to_string(::getpid());
  if (!suffix.empty()) {
    name += '-';
    name += suffix;
  }
  return path.parent_path() / name;
}

std::filesystem::path newPartialFilePath(const std::filesystem::path& target) {
  static std::atomic<std::uint64_t> counter{0};
  return partialOutputPath(target, std::to_string(counter.fetch_add(1)));
}

bool processIsAlive(pid_t pid) {
  if (pid <= 0) return false;
  return ::kill(pid, 0) == 0 || errno == EPERM;
}

std::vector<PartialOutput> findPartialOutputs(const std::filesystem::path& target) {
  const std::filesystem::path path = normalTarget(target);
  std::filesystem::path folder = path.parent_path();
  if (folder.empty()) folder = ".";
  std::string prefix = ".";
  prefix += path.filename().string();
  prefix += ".partial-";
  std::vector<PartialOutput> found;
  std::error_code error;
  for (std::filesystem::directory_iterator it(folder, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(prefix)) continue;
    const pid_t pid = pidOf(std::string_view(name).substr(prefix.size()));
    if (pid == 0) continue;
    found.push_back({it->path(), pid, 0});
  }
  std::sort(found.begin(), found.end(),
            [](const PartialOutput& a, const PartialOutput& b) { return a.path < b.path; });
  return found;
}

PartialCleanup removeStalePartialOutputs(const std::filesystem::path& target) {
  PartialCleanup cleanup;
  for (PartialOutput& partial : findPartialOutputs(target)) {
    partial.bytes = bytesIn(partial.path);
    if (processIsAlive(partial.pid)) {
      cleanup.running.push_back(partial);
      continue;
    }
    std::error_code error;
    std::filesystem::remove_all(partial.path, error);
    if (error) {
      cleanup.running.push_back(partial);  // could not be removed: left, and said so
      continue;
    }
    cleanup.freed_bytes += partial.bytes;
    cleanup.removed.push_back(std::move(partial));
  }
  return cleanup;
}

void requireOutputFolder(const std::filesystem::path& output, const std::string& option) {
  const std::filesystem::path folder = output.has_parent_path() ? output.parent_path() : ".";
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) {
    throw std::invalid_argument(option + " " + output.string() + ": the folder " + folder.string() +
                                " does not exist");
  }
}

void requireOutputIsNotInput(const std::filesystem::path& output,
                             const std::filesystem::path& input, const std::string& option,
                             const std::string& kind) {
  std::error_code error;
  if (std::filesystem::equivalent(output, input, error)) {
    throw std::invalid_argument(option + " " + output.string() +
                                ": is the input point file, which the " + kind +
                                " would replace: expected another file");
  }
}

std::string formatBytes(std::uint64_t bytes) {
  char text[32];
  if (bytes >= 1'000'000'000) {
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  } else if (bytes >= 1'000'000) {
    std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / 1e6);
  } else if (bytes >= 1'000) {
    std::snprintf(text, sizeof text, "%.1f kB", double(bytes) / 1e3);
  } else {
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  }
  return text;
}

}  // namespace parallax
