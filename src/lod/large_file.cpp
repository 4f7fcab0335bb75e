#include "lod/large_file.h"

#include <exception>
#include <system_error>

#include "io/point_file.h"
#include "io/text_reader.h"

namespace parallax {
namespace {

// The fewest bytes a point takes in a text file: "1 2 3\n".
constexpr std::uint64_t kMinTextBytesPerPoint = 6;

}  // namespace

std::optional<std::uint64_t> pointsOverBudget(const std::filesystem::path& path,
                                              std::uint64_t budget) {
  std::optional<std::uint64_t> points = headerPointCount(path);
  if (!points) {
    std::error_code error;
    const std::uint64_t bytes = std::filesystem::file_size(path, error);
    if (error || bytes / kMinTextBytesPerPoint <= budget) return std::nullopt;
    try {
      const PointFormat format = detectPointFormat(path);
      if (format != PointFormat::Text && format != PointFormat::Pts) return std::nullopt;
      points = countTextPoints(path);
    } catch (const std::exception&) {
      return std::nullopt;  // the ordinary read says what is wrong
    }
  }
  if (*points > budget) return points;
  return std::nullopt;
}

}  // namespace parallax
