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

// The progress of one step of a command (reading, writing, re-encoding): a TerminalProgress bar
// on stderr, or, while a progress observer is set (progress_observer.h), a stage reported to it
// under the bar's label, as the octree stages are. core/progress.h's Progress has no finish()
// (adding one would rebuild nearly every module), so the two are wrapped here.
class CommandProgress final : public Progress {
 public:
  explicit CommandProgress(std::unique_ptr<TerminalProgress> bar);
  explicit CommandProgress(std::unique_ptr<Progress> observed);
  ~CommandProgress() override;

  void advance(std::uint64_t amount) override { target_->advance(amount); }
  // The bar's last line, or the observer's report of the final count; once (the destructor
  // does it too).
  void finish();

 private:
  std::unique_ptr<TerminalProgress> bar_;
  std::unique_ptr<Progress> observed_;  // finishes when destroyed
  Progress* target_;
};

// A bar for `label` over `total` (in `unit`), or the observer's stage `label`; none when quiet
// and no observer is set.
std::unique_ptr<CommandProgress> progressBar(bool quiet, const std::string& label,
                                             std::uint64_t total,
                                             const std::string& unit = "points");

// The bar for reading a point file with readPointFile: over its points when its header says how
// many (PLY, LAS), else over its bytes (text, which the text reader advances by bytes; an
// observer then sees the stage `label` + " bytes").
std::unique_ptr<CommandProgress> readingBar(bool quiet, const std::string& label,
                                            const std::filesystem::path& path);

// One bar per stage of an octree conversion (lod/potree_converter.h), or none when quiet.
ProgressFactory stageBars(bool quiet);

}  // namespace parallax::cli
