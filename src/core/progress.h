// Progress of long work (loading, generating, converting), reported from any thread.
//
// The library calls `advance()`; what is shown is the sink's business. `TerminalProgress` draws a
// bar with rate and ETA on standard error when it is a terminal, and nothing otherwise (logs and
// CI stay clean).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace parallax {

class Progress {
 public:
  virtual ~Progress() = default;
  // Thread-safe; `amount` is in the unit the total was given in.
  virtual void advance(std::uint64_t amount) = 0;
};

class TerminalProgress final : public Progress {
 public:
  // `unit` names what is counted ("points", "MB"); `total` 0 means unknown.
  TerminalProgress(std::string label, std::uint64_t total, std::string unit = "points");
  ~TerminalProgress() override;

  void advance(std::uint64_t amount) override;
  // Draws the final state and a newline (also done by the destructor).
  void finish();

  static bool stderrIsTerminal();

 private:
  void draw();

  std::string label_;
  std::string unit_;
  std::uint64_t total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<std::int64_t> next_draw_ns_{0};
  std::chrono::steady_clock::time_point start_;
  std::mutex draw_mutex_;
};

}  // namespace parallax
