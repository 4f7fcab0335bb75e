#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace parallax {
namespace {

constexpr std::int64_t kRedrawIntervalNs = 100'000'000;  // 10 Hz is smooth and costs nothing

std::string formatDuration(double seconds) {
  char text[32];
  auto total = static_cast<long long>(seconds + 0.5);
  if (total >= 3600) {
    std::snprintf(text, sizeof text, "%lldh%02lldm", total / 3600, (total / 60) % 60);
  } else {
    std::snprintf(text, sizeof text, "%lldm%02llds", total / 60, total % 60);
  }
  return text;
}

}  // namespace

TerminalProgress::TerminalProgress(std::string label, std::uint64_t total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(stderrIsTerminal()),
      start_(std::chrono::steady_clock::now()) {}

TerminalProgress::~TerminalProgress() {
  finish();
}

bool TerminalProgress::stderrIsTerminal() {
  return isatty(STDERR_FILENO) == 1;
}

void TerminalProgress::advance(std::uint64_t amount) {
  done_.fetch_add(amount, std::memory_order_relaxed);
  if (!enabled_) return;
  auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                    std::chrono::steady_clock::now() - start_)
                    .count();
  auto due = next_draw_ns_.load(std::memory_order_relaxed);
  if (now_ns < due) return;
  if (!next_draw_ns_.compare_exchange_strong(due, now_ns + kRedrawIntervalNs)) return;
  draw();
}

void TerminalProgress::finish() {
  std::lock_guard lock(draw_mutex_);
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::uint64_t done = done_.load();
  double rate = seconds > 0 ? done / seconds : 0.0;
  std::fprintf(stderr, "\r\033[K%s: %llu %s in %.2f s (%.2f M %s/s)\n", label_.c_str(),
               static_cast<unsigned long long>(done), unit_.c_str(), seconds, rate / 1e6,
               unit_.c_str());
}

void TerminalProgress::draw() {
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_) return;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::uint64_t done = done_.load(std::memory_order_relaxed);
  double rate = seconds > 0 ? done / seconds : 0.0;
  constexpr int kWidth = 30;
  if (total_ > 0) {
    double fraction = std::min(1.0, double(done) / double(total_));
    int filled = int(fraction * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::string eta = rate > 0 ? formatDuration((total_ - std::min(done, total_)) / rate) : "?";
    std::fprintf(stderr, "\r\033[K%s [%s] %5.1f%%  %.2f M %s/s  ETA %s", label_.c_str(),
                 bar.c_str(), fraction * 100.0, rate / 1e6, unit_.c_str(), eta.c_str());
  } else {
    std::fprintf(stderr, "\r\033[K%s %llu %s  %.2f M %s/s", label_.c_str(),
                 static_cast<unsigned long long>(done), unit_.c_str(), rate / 1e6, unit_.c_str());
  }
  std::fflush(stderr);
}

}  // namespace parallax
