// The attributes a point filter's tests read, so that a reader asked for fewer attributes
// (core/attribute_selection.h) still gives what the filter needs: `render` (attributesDrawn) and
// the octree builder (lod's PointStream) ask for these beside their own.
#pragma once

#include <string>
#include <vector>

#include "core/column_names.h"
#include "core/point_filter.h"

namespace parallax {

// By the model's names (column_names.h): "classification" when the filter keeps only some
// classes, "return_number" and "number_of_returns" for returns, "intensity" and "gps_time" for
// their ranges. Positions are not listed (every reader gives them).
inline std::vector<std::string> attributesTested(const PointFilter& filter) {
  std::vector<std::string> names;
  if (!filter.keepsEveryClass()) names.emplace_back(column_names::kClassification);
  if (!filter.keepsEveryReturn()) {
    names.emplace_back(column_names::kReturnNumber);
    names.emplace_back(column_names::kNumberOfReturns);
  }
  if (filter.intensity) names.emplace_back(column_names::kIntensity);
  if (filter.gps_time) names.emplace_back(column_names::kGpsTime);
  return names;
}

}  // namespace parallax
