// Opening a point file too large to draw whole, for `parallax view FILE` and `parallax render
// FILE`: how many points a file holds (from its header, without reading it), where its
// level-of-detail octree lives (the user's cache, a --cache-dir, or a temporary folder removed at
// exit with --no-cache), and the conversion into it, in the foreground (render, with a progress
// bar) or on a background thread (view, with a progress the panel reads).
//
// The octree is a Potree 2.0 directory written by convertToPotree (lod/potree_converter.h), which
// renames a finished conversion into place: a complete directory in the cache is reused as it is
// (lod/octree_cache.h names it by the file's path, size and modification time).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "lod/octree_build_options.h"
#include "lod/potree_converter.h"

namespace parallax {

// The most points a preview (the first picture of a file over the budget) samples: at 1280 x 720,
// about one a pixel, and read, uploaded and drawn on llvmpipe in well under a second where the
// default budget's 3 M take over two.
constexpr std::uint64_t kPreviewPoints = 1'000'000;

// The point count in a PLY or LAS file's header; std::nullopt for text files (no count without
// reading them) and for anything that cannot be read (the caller's normal read reports why).
std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path);

struct OctreeCacheSettings {
  bool use_cache = true;            // false: a temporary folder, removed when the owner ends
  std::filesystem::path cache_dir;  // empty: octreeCacheRoot() (XDG_CACHE_HOME, ~/.cache)
  OctreeBuildOptions build;         // sampling, memory budget, threads
};

// Where the octree of one file goes. Removes its directory on destruction when temporary.
class OctreeLocation {
 public:
  // Throws std::runtime_error when the cache is wanted but has no home (no XDG_CACHE_HOME, no
  // HOME, no --cache-dir), and std::filesystem::filesystem_error when `input` cannot be read.
  OctreeLocation(const std::filesystem::path& input, const OctreeCacheSettings& settings);
  ~OctreeLocation();
  OctreeLocation(const OctreeLocation&) = delete;
  OctreeLocation& operator=(const OctreeLocation&) = delete;

  const std::filesystem::path& input() const { return input_; }
  const std::filesystem::path& directory() const { return directory_; }
  bool temporary() const { return !temporary_root_.empty(); }
  // A finished octree is already there (a cache hit).
  bool complete() const;
  // For a process about to end during a conversion (no destructors run): removes what the
  // conversion has written so far, the converter's ".NAME.partial-PID" folder, and the temporary
  // folder. Never throws.
  void abandon() const noexcept;

 private:
  std::filesystem::path input_, directory_, temporary_root_;
};

// Converts `location.input()` into `location.directory()` unless it is complete already; true
// when it converted. Progress as convertToPotree's `progress`. Throws what convertToPotree throws.
bool ensureOctree(const OctreeLocation& location, const OctreeBuildOptions& build,
                  const ProgressFactory& progress);

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
