#include "lod/background_octree_build.h"

#include <exception>
#include <utility>

namespace parallax {

// One converter stage's progress, written into the build's counters.
class BackgroundOctreeBuild::StageProgress final : public Progress {
 public:
  explicit StageProgress(BackgroundOctreeBuild& build) : build_(build) {}
  void advance(std::uint64_t amount) override { build_.done_ += amount; }

 private:
  BackgroundOctreeBuild& build_;
};

BackgroundOctreeBuild::BackgroundOctreeBuild(std::unique_ptr<OctreeLocation> location,
                                             const OctreeBuildOptions& build)
    : location_(std::move(location)), start_(std::chrono::steady_clock::now()) {
  thread_ = std::thread([this, build] {
    const ProgressFactory progress = [this](const std::string& stage, std::uint64_t total) {
      {
        const std::lock_guard lock(mutex_);
        stage_ = stage;
      }
      done_ = 0;
      total_ = total;
      return std::make_unique<StageProgress>(*this);
    };
    try {
      ensureOctree(*location_, build, progress);
    } catch (const std::exception& e) {
      const std::lock_guard lock(mutex_);
      error_ = e.what();
      if (error_.empty()) error_ = "the conversion failed";
    }
    finished_ = true;
  });
}

BackgroundOctreeBuild::~BackgroundOctreeBuild() {
  if (thread_.joinable()) thread_.join();
}

std::unique_ptr<OctreeLocation> BackgroundOctreeBuild::takeLocation() {
  if (thread_.joinable()) thread_.join();
  return std::move(location_);
}

BackgroundOctreeBuild::Status BackgroundOctreeBuild::status() const {
  Status status;
  status.finished = finished_;
  status.done = done_;
  status.total = total_;
  const std::lock_guard lock(mutex_);
  status.stage = stage_;
  status.error = error_;
  return status;
}

double BackgroundOctreeBuild::secondsElapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace parallax
