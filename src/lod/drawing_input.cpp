#include "lod/drawing_input.h"

#include <algorithm>

#include "io/point_file.h"
#include "lod/large_file.h"
#include "lod/octree_open.h"

namespace parallax {

DrawingInput planDrawing(const std::filesystem::path& input, std::uint64_t budget) {
  if (isOctreePath(input)) return {.kind = DrawingKind::Octree};
  if (const std::optional<std::uint64_t> points = pointsOverBudget(input, budget)) {
    return {.kind = DrawingKind::OverBudget, .points = *points};
  }
  return {.kind = DrawingKind::WholeFile};
}

std::optional<PointCloud> readDrawingPreview(const std::filesystem::path& input,
                                             std::uint64_t budget) {
  if (!hasPointFilePreview(detectPointFormat(input))) return std::nullopt;
  return readPointFilePreview(input, std::min(budget, kPreviewPoints));
}

}  // namespace parallax
