#include "progress_options.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <system_error>

#include "core/throttled_progress.h"
#include "io/point_file.h"
#include "progress_observer.h"

namespace parallax::cli {

namespace {

std::mutex observer_mutex;
std::shared_ptr<const ProgressObserver> current_observer;

std::shared_ptr<const ProgressObserver> observer() {
  const std::lock_guard lock(observer_mutex);
  return current_observer;
}

// A stage's progress reported to the observer (progress_observer.h says how often).
class ObservedStage final : public ThrottledProgress {
 public:
  ObservedStage(std::shared_ptr<const ProgressObserver> observer, std::string label,
                std::uint64_t total)
      : ThrottledProgress(total), observer_(std::move(observer)), label_(std::move(label)) {}
  ~ObservedStage() override {
    const std::lock_guard lock(report_mutex_);
    (*observer_)(label_, done(), total());
  }
  ObservedStage(const ObservedStage&) = delete;
  ObservedStage& operator=(const ObservedStage&) = delete;

 private:
  void report(std::uint64_t done) override { (*observer_)(label_, done, total()); }

  std::shared_ptr<const ProgressObserver> observer_;
  std::string label_;
};

}  // namespace

void setProgressObserver(ProgressObserver observer) {
  const std::lock_guard lock(observer_mutex);
  current_observer =
      observer ? std::make_shared<const ProgressObserver>(std::move(observer)) : nullptr;
}

void addQuietFlag(CLI::App& command, bool& quiet) {
  command.add_flag("-q,--quiet", quiet, "No progress bar and no report on stderr (errors only)");
}

CommandProgress::CommandProgress(std::unique_ptr<TerminalProgress> bar)
    : bar_(std::move(bar)), target_(bar_.get()) {}
CommandProgress::CommandProgress(std::unique_ptr<Progress> observed)
    : observed_(std::move(observed)), target_(observed_.get()) {}
CommandProgress::~CommandProgress() {
  finish();
}

void CommandProgress::finish() {
  if (bar_) bar_->finish();
  observed_.reset();  // its destructor reports the final count
}

std::unique_ptr<CommandProgress> progressBar(bool quiet, const std::string& label,
                                             std::uint64_t total, const std::string& unit) {
  if (auto observing = observer()) {
    return std::make_unique<CommandProgress>(
        std::unique_ptr<Progress>(std::make_unique<ObservedStage>(observing, label, total)));
  }
  if (quiet) return nullptr;
  return std::make_unique<CommandProgress>(std::make_unique<TerminalProgress>(label, total, unit));
}

std::unique_ptr<CommandProgress> readingBar(bool quiet, const std::string& label,
                                            const std::filesystem::path& path) {
  if (quiet && !observer()) return nullptr;
  if (const auto points = headerPointCount(path)) return progressBar(quiet, label, *points);
  std::error_code error;
  const std::uint64_t bytes = std::filesystem::file_size(path, error);
  return progressBar(quiet, observer() ? label + " bytes" : label, error ? 0 : bytes, "bytes");
}

ProgressFactory stageBars(bool quiet) {
  if (auto observing = observer()) {
    return [observing](const std::string& stage, std::uint64_t total) -> std::unique_ptr<Progress> {
      return std::make_unique<ObservedStage>(observing, stage, total);
    };
  }
  if (quiet) return {};
  return [](const std::string& stage, std::uint64_t total) -> std::unique_ptr<Progress> {
    return std::make_unique<TerminalProgress>(stage, total);
  };
}

}  // namespace parallax::cli
