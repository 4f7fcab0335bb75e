// The Processing panel's state in a viewer session (internal to src/viewer; process_panel.cpp):
// the steps typed, where the result goes, and the run under way on its own thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "process/process_runner.h"

namespace parallax::viewer_internal {

// What the run's thread reports and the panel's progress bar reads: the stage under way
// ("reading", "tiling", a step, "writing") and how far it is.
struct ProcessProgress {
  std::mutex mutex;
  std::string stage;  // guarded by mutex
  std::atomic<std::uint64_t> done{0}, total{0};
  // The Cancel button: the run stops at its next tile. Set through requestCancel, which wakes a
  // held run.
  std::atomic<bool> cancel{false};
  // A test hook (PARALLAX_VIEW_TEST_HOLD_PROCESS=1): the run's first progress report waits until
  // Cancel is pressed, so that a window test cancels a run of any size while it is under way,
  // without timing it. `held`: that report has come.
  bool hold_first_report = false;
  std::atomic<bool> held{false};

  void requestCancel() {
    cancel = true;
    cancel.notify_all();
  }
};

struct ProcessSession {
  // One step a line, as parseProcessStep (process/process_steps.h) reads it: "normals 16".
  std::vector<std::string> steps;
  std::string new_step = "normals 16";  // the field of the step to add
  std::string output;                   // the result's file (its extension picks the format)
  // Only the points of the clip box while it is on (what is shown; the panel's checkbox).
  bool clip_box_only = true;
  // The run under way (valid() while it is), what it writes, its steps and when it started.
  std::future<ProcessReport> run;
  std::shared_ptr<ProcessProgress> progress;
  std::filesystem::path running_output;
  std::vector<ProcessStep> running_steps;
  std::chrono::steady_clock::time_point started;
  std::string message;             // the last run's outcome, or why it could not start
  bool run_requested = false;      // the K key: run the steps at the next frame
  bool hold_first_report = false;  // ProcessProgress::hold_first_report for the next runs
  // With PARALLAX_VIEW_TRACE_KEYS: the Cancel button's place was logged for the run under way.
  bool cancel_button_logged = false;

  ProcessSession() = default;
  ProcessSession(const ProcessSession&) = delete;
  ProcessSession& operator=(const ProcessSession&) = delete;
  // A run under way is cancelled (its output and work files removed) and waited for: quitting
  // does not wait for the whole run.
  ~ProcessSession() {
    if (run.valid() && progress) progress->requestCancel();
  }
};

}  // namespace parallax::viewer_internal
