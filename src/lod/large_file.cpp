#include "lod/large_file.h"

#include "io/point_file.h"

namespace parallax {

std::optional<std::uint64_t> pointsOverBudget(const std::filesystem::path& path,
                                              std::uint64_t budget) {
  const std::optional<std::uint64_t> points = headerPointCount(path);
  if (points && *points > budget) return points;
  return std::nullopt;
}

}  // namespace parallax
