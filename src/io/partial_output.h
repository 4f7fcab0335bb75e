// Partial outputs: every writer writes under a temporary name beside its target and renames it
// to the target only when complete (point_file.h's OutputFile, the PLY writer, the octree
// converter), so a killed process never leaves a truncated file under the name asked for. The
// temporary name is hidden and carries the writer's process id:
//
//   .NAME.partial-PID       a directory (lod/potree_converter.h)
//   .NAME.partial-PID-N     a file (N tells apart the outputs of one process)
//
// A process killed outright (SIGKILL, power loss) cannot remove its partial output; the next
// conversion to the same target does (`parallax convert`, and `convert --clean`), when the process
// in the name is gone. A partial output whose process is alive is never touched: it may be a
// conversion running beside this one. (A process id reused by an unrelated process keeps a stale
// partial output until that process ends: the safe side. Processes in another PID namespace
// sharing the folder are not told apart.)
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace parallax {

// ".NAME.partial-PID" beside `target` (its parent folder), with "-" + `suffix` when not empty.
// `target` may end in '/' (a directory).
std::filesystem::path partialOutputPath(const std::filesystem::path& target,
                                        const std::string& suffix = "");

// A fresh ".NAME.partial-PID-N" for a file written to `target`: N from a process-wide counter, so
// two writers of one target in one process never share it.
std::filesystem::path newPartialFilePath(const std::filesystem::path& target);

// True when a process with this id exists (kill(pid, 0) succeeds or is refused for permission).
bool processIsAlive(pid_t pid);

struct PartialOutput {
  std::filesystem::path path;
  pid_t pid = 0;
  std::uint64_t bytes = 0;  // of every regular file in it (not following links)
};

struct PartialCleanup {
  std::vector<PartialOutput> removed;  // their process was gone
  std::vector<PartialOutput> running;  // left alone: their process is alive
  std::uint64_t freed_bytes = 0;
};

// The partial outputs of `target` in its folder, sorted by name.
std::vector<PartialOutput> findPartialOutputs(const std::filesystem::path& target);

// Removes the partial outputs of `target` whose process is gone and says what it freed. Never
// throws for a folder that does not exist; a partial output that cannot be removed is reported
// as running (left where it is) rather than failing the conversion.
PartialCleanup removeStalePartialOutputs(const std::filesystem::path& target);

// The checks every command makes of an output before any work, so that a mistake in a path fails
// at once rather than after hours (GDAL's or a rename's error at the end). `option` names it in
// messages ("-o", "--raster-out"); both throw std::invalid_argument.
// The output's folder exists (a point file or a GeoTIFF goes into an existing folder; octree
// outputs make theirs).
void requireOutputFolder(const std::filesystem::path& output, const std::string& option);
// The output is not `input`, which writing a `kind` ("GeoTIFF") over it would replace.
void requireOutputIsNotInput(const std::filesystem::path& output,
                             const std::filesystem::path& input, const std::string& option,
                             const std::string& kind);

// "1.4 GB", "12.0 MB", "512 bytes": for messages.
std::string formatBytes(std::uint64_t bytes);

}  // namespace parallax
