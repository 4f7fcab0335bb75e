// Format detection and reading of any supported point file.
#pragma once

#include <filesystem>
#include <string>

#include "core/point_cloud.h"
#include "core/progress.h"

namespace parallax {

enum class PointFormat { Ply, Unknown };

// Detects the format from the file's first bytes (magic and header), not from its extension.
// Throws InputError when the file cannot be opened.
PointFormat detectPointFormat(const std::filesystem::path& path);

struct PointReadOptions {
  Progress* progress = nullptr;
  bool parallel = true;
};

// Reads a whole point file of any supported format. Throws InputError for unreadable or malformed
// files, and for an unknown format with the list of supported ones.
PointCloud readPointFile(const std::filesystem::path& path, const PointReadOptions& options = {});

}  // namespace parallax
