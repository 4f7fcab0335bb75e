// "Open this input for drawing": the decision `parallax render`, `parallax pick` and `parallax
// view` share. An octree (a Potree directory or a COPC file) is streamed; a point file within the
// frame's budget is read whole; a larger one is drawn from its octree (octree_cache.h), with an
// even sample as a first picture where the format has a sample reader. Each front end then does
// its own part (converting at once, or in the background while the sample shows).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/point_cloud.h"

namespace parallax {

enum class DrawingKind {
  Octree,     // a Potree directory or a COPC file: opened with openOctree
  WholeFile,  // a point file within the budget: read whole, every point drawn
  OverBudget  // a point file over the budget: drawn from its octree
};

struct DrawingInput {
  DrawingKind kind = DrawingKind::WholeFile;
  std::uint64_t points = 0;  // OverBudget: the file's point count
};

// How `input` is drawn with a frame budget of `budget` points. Reads only what telling needs
// (the octree's marker files, the point file's header or counting pass; large_file.h).
DrawingInput planDrawing(const std::filesystem::path& input, std::uint64_t budget);

// The first picture of a file over the budget: an even sample of at most min(budget,
// kPreviewPoints) points, or std::nullopt where the format has no sample reader (text).
std::optional<PointCloud> readDrawingPreview(const std::filesystem::path& input,
                                             std::uint64_t budget);

// A file drawn whole is read with the attributes its first picture needs (PointReadOptions::
// attributes: a LAZ of formats 6-10 then decodes only those layers; other readers may fill every
// column anyway), and the others when first asked for (a colour mode, a filter, a pick):
//
// Reads from `path` (the file `cloud` was read from, with fewer attributes) those of `wanted`
// that the file holds (`file_attributes`: readPointFileHeader's names) and `cloud` lacks, and
// adds their columns to `cloud`. Its positions and the columns it has stay as they are; its
// scalar columns end in the order of `file_attributes`, as a full read gives them. The reader
// still decodes the positions (every other LAZ layer takes its contexts from them) but they are
// not copied into `cloud`. Returns the names added, empty when nothing was missing (no read).
// Throws InputError as readPointFile does, and when the file no longer holds `cloud.count` points.
std::vector<std::string> readMissingAttributes(const std::filesystem::path& path,
                                               const std::vector<std::string>& file_attributes,
                                               const AttributeSelection& wanted, PointCloud& cloud);

}  // namespace parallax
