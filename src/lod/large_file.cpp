#include "lod/large_file.h"

#include <algorithm>
#include <exception>
#include <system_error>

#include "io/point_file.h"

namespace parallax {

std::optional<std::uint64_t> pointsOverBudget(const std::filesystem::path& path,
                                              std::uint64_t budget) {
  std::optional<std::uint64_t> points = headerPointCount(path);
  if (!points) {
    // A format whose header states no count (text) is counted by a pass over the file, only
    // when the file is large enough to hold more than `budget` of its smallest points.
    std::error_code error;
    const std::uint64_t bytes = std::filesystem::file_size(path, error);
    if (error) return std::nullopt;
    try {
      const PointFormatEntry* row = detectPointFormat(path).entry();
      if (row == nullptr || !row->count_points) return std::nullopt;
      if (bytes / std::max<std::uint64_t>(row->min_point_bytes, 1) <= budget) return std::nullopt;
      points = row->count_points(path);
    } catch (const std::exception&) {
      return std::nullopt;  // the ordinary read says what is wrong
    }
  }
  if (*points > budget) return points;
  return std::nullopt;
}

}  // namespace parallax
