// Where `parallax view FILE` keeps the octree it built for a file, so a second visit opens at
// once: $XDG_CACHE_HOME/parallax/octrees (else ~/.cache/parallax/octrees), one Potree 2.0
// directory per input, named after the file and a hash of its absolute path, size and
// modification time (an edited file gets a new octree; old ones are left for the user to clear).
#pragma once

#include <filesystem>
#include <optional>

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

}  // namespace parallax
