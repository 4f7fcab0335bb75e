#include "lod/octree_cache.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace parallax {

namespace {

// FNV-1a, 64 bits: enough to keep the octrees of different files apart in one folder (the file
// name is part of the directory name too); not a security boundary.
std::uint64_t fnv1a(const std::string& text, std::uint64_t hash = 14695981039346656037ull) {
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace

std::optional<std::filesystem::path> octreeCacheRoot() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/') {
    return std::filesystem::path(xdg) / "parallax" / "octrees";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return std::filesystem::path(home) / ".cache" / "parallax" / "octrees";
  }
  return std::nullopt;
}

std::filesystem::path cachedOctreePath(const std::filesystem::path& root,
                                       const std::filesystem::path& input) {
  const std::filesystem::path absolute = std::filesystem::canonical(input);
  const auto size = std::filesystem::file_size(absolute);
  const auto mtime = std::filesystem::last_write_time(absolute).time_since_epoch();
  const std::string key =
      absolute.string() + '\n' + std::to_string(size) + '\n' +
      std::to_string(std::chrono::duration_cast<std::chrono::nanoseconds>(mtime).count());
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fnv1a(key)));
  return root / (absolute.filename().string() + "-" + hash);
}

bool isCompleteOctree(const std::filesystem::path& directory) {
  std::error_code error;
  for (const char* name : {"metadata.json", "hierarchy.bin", "octree.bin"}) {
    if (!std::filesystem::is_regular_file(directory / name, error)) return false;
  }
  return std::filesystem::file_size(directory / "metadata.json", error) > 0 && !error;
}

}  // namespace parallax
