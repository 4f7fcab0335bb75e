// The conversion of a file into its cached octree (octree_cache.h: ensureOctree) on a thread of
// its own, with its progress readable from a frame loop: what `parallax view FILE` runs while it
// shows a preview. The window reads status() each frame and takes the location once finished.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "lod/octree_build_options.h"
#include "lod/octree_cache.h"

namespace parallax {

// ensureOctree on a thread of its own, with its progress readable from the frame loop.
class BackgroundOctreeBuild {
 public:
  explicit BackgroundOctreeBuild(std::unique_ptr<OctreeLocation> location,
                                 const OctreeBuildOptions& build);
  ~BackgroundOctreeBuild();  // waits for the conversion (it cannot be interrupted)
  BackgroundOctreeBuild(const BackgroundOctreeBuild&) = delete;
  BackgroundOctreeBuild& operator=(const BackgroundOctreeBuild&) = delete;

  struct Status {
    std::string stage;  // "scanning", "counting", ... as the converter names them
    std::uint64_t done = 0, total = 0;
    bool finished = false;
    std::string error;  // non-empty when the conversion failed
  };
  Status status() const;
  const OctreeLocation& location() const { return *location_; }
  // Once status().finished: waits for the thread and hands the location over (its temporary
  // folder, if any, lives as long as the returned object).
  std::unique_ptr<OctreeLocation> takeLocation();
  double secondsElapsed() const;

 private:
  class StageProgress;

  std::unique_ptr<OctreeLocation> location_;
  mutable std::mutex mutex_;
  std::string stage_, error_;
  std::atomic<std::uint64_t> done_{0}, total_{0};
  std::atomic<bool> finished_{false};
  std::chrono::steady_clock::time_point start_;
  std::thread thread_;
};

}  // namespace parallax
