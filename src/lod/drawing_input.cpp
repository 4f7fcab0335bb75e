#include "lod/drawing_input.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
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

namespace {

bool namedIn(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Moves the columns of `more` (a read of the same file, same points) that `cloud` lacks into it.
void addMissingColumns(PointCloud& cloud, PointCloud&& more) {
  if (!cloud.hasColors() && more.hasColors()) {
    cloud.colors = std::move(more.colors);
    cloud.stored_colors = std::move(more.stored_colors);
    cloud.source.color = more.source.color;
    cloud.source.has_alpha = more.source.has_alpha;
  }
  if (!cloud.hasNormals() && more.hasNormals()) {
    cloud.normals = std::move(more.normals);
    cloud.source.normal = more.source.normal;
  }
  if (!cloud.hasIntensity() && more.hasIntensity()) {
    cloud.intensity = std::move(more.intensity);
    cloud.source.intensity = more.source.intensity;
  }
  if (!cloud.hasClassification() && more.hasClassification()) {
    cloud.classification = std::move(more.classification);
    cloud.source.classification = more.source.classification;
  }
  for (ScalarColumn& column : more.scalars) {
    if (!cloud.findScalar(column.name)) cloud.scalars.push_back(std::move(column));
  }
}

}  // namespace

std::vector<std::string> readMissingAttributes(const std::filesystem::path& path,
                                               const std::vector<std::string>& file_attributes,
                                               const AttributeSelection& wanted,
                                               PointCloud& cloud) {
  const std::vector<std::string> held = cloud.attributeNames();
  std::vector<std::string> missing;
  for (const std::string& name : file_attributes) {
    if (wanted.wants(name) && !namedIn(held, name)) missing.push_back(name);
  }
  if (missing.empty()) return {};
  PointCloud more = readPointFile(path, {.attributes = AttributeSelection::only(missing)});
  if (more.count != cloud.count) {
    throw InputError({.file = path.string(),
                      .element = "points",
                      .expected = std::to_string(cloud.count) + " points, as when it was opened",
                      .found = std::to_string(more.count) + " (the file changed on disk)",
                      .hint = "open it again"});
  }
  addMissingColumns(cloud, std::move(more));
  // Scalars in the file's order, as a full read lists them (an unlisted one goes last).
  const auto rank = [&](const ScalarColumn& column) {
    return std::find(file_attributes.begin(), file_attributes.end(), column.name) -
           file_attributes.begin();
  };
  std::stable_sort(cloud.scalars.begin(), cloud.scalars.end(),
                   [&](const ScalarColumn& a, const ScalarColumn& b) { return rank(a) < rank(b); });
  std::vector<std::string> added;
  const std::vector<std::string> now = cloud.attributeNames();
  for (const std::string& name : now) {
    if (!namedIn(held, name)) added.push_back(name);
  }
  return added;
}

}  // namespace parallax
