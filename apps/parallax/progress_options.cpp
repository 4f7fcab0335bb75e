#include "progress_options.h"

#include <system_error>

#include "io/point_file.h"

namespace parallax::cli {

void addQuietFlag(CLI::App& command, bool& quiet) {
  command.add_flag("-q,--quiet", quiet, "No progress bar and no report on stderr (errors only)");
}

std::unique_ptr<TerminalProgress> progressBar(bool quiet, const std::string& label,
                                              std::uint64_t total, const std::string& unit) {
  if (quiet) return nullptr;
  return std::make_unique<TerminalProgress>(label, total, unit);
}

std::unique_ptr<TerminalProgress> readingBar(bool quiet, const std::string& label,
                                             const std::filesystem::path& path) {
  if (quiet) return nullptr;
  if (const auto points = headerPointCount(path)) {
    return std::make_unique<TerminalProgress>(label, *points, "points");
  }
  std::error_code error;
  const std::uint64_t bytes = std::filesystem::file_size(path, error);
  return std::make_unique<TerminalProgress>(label, error ? 0 : bytes, "bytes");
}

ProgressFactory stageBars(bool quiet) {
  if (quiet) return {};
  return [](const std::string& stage, std::uint64_t total) -> std::unique_ptr<Progress> {
    return std::make_unique<TerminalProgress>(stage, total);
  };
}

}  // namespace parallax::cli
