// Where the level-of-detail octree of a point file lives when `parallax view FILE` or `parallax
// render FILE` needs one (the file holds more points than the budget), and its conversion there.
//
// The cache: $XDG_CACHE_HOME/parallax/octrees (else ~/.cache/parallax/octrees), one Potree 2.0
// directory per input, named after the file and a hash of its absolute path, size and
// modification time (an edited file gets a new octree; old ones are left for the user to clear).
// With --cache-dir DIR the same names under DIR; with --no-cache a temporary folder removed when
// its OctreeLocation ends.
//
// The octree is written by convertToPotree (potree_converter.h), which renames a finished
// conversion into place: a complete directory in the cache is reused as it is. The conversion on
// a thread of its own, for a window that must keep answering, is background_octree_build.h.
#pragma once

#include <filesystem>
#include <optional>

#include "lod/convert_stages.h"
#include "lod/octree_build_options.h"

namespace parallax {

// The cache folder; std::nullopt when neither XDG_CACHE_HOME nor HOME is set.
std::optional<std::filesystem::path> octreeCacheRoot();

// The directory the octree of `input` has (or would have) in `root`. Throws
// std::filesystem::filesystem_error when the input cannot be inspected.
std::filesystem::path cachedOctreePath(const std::filesystem::path& root,
                                       const std::filesystem::path& input);

// True when `directory` holds a finished conversion (the writer renames a finished octree into
// place, so a complete metadata.json, hierarchy.bin and octree.bin mean it is whole).
bool isCompleteOctree(const std::filesystem::path& directory);

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

}  // namespace parallax
