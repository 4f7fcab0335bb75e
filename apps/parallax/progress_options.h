// -q/--quiet and the progress bar, the same on every long-running command (generate, convert,
// info, render, bench): without -q, work that takes a while draws core/progress.h's
// TerminalProgress bar on stderr (when stderr is a terminal; logs and pipes stay clean), and a
// command's report on stderr is printed; with -q neither is, and only errors (and a command's
// results on stdout: info, bench) remain.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "core/progress.h"
#include "lod/convert_stages.h"

namespace parallax::cli {

// Registers -q,--quiet on `command`.
void addQuietFlag(CLI::App& command, bool& quiet);

// A bar for `label` over `total` (in `unit`), or none when quiet.
std::unique_ptr<TerminalProgress> progressBar(bool quiet, const std::string& label,
                                              std::uint64_t total,
                                              const std::string& unit = "points");

// The bar for reading a point file with readPointFile: over its points when its header says how
// many (PLY, LAS), else over its bytes (text, which the text reader advances by bytes).
std::unique_ptr<TerminalProgress> readingBar(bool quiet, const std::string& label,
                                             const std::filesystem::path& path);

// One bar per stage of an octree conversion (lod/potree_converter.h), or none when quiet.
ProgressFactory stageBars(bool quiet);

}  // namespace parallax::cli
