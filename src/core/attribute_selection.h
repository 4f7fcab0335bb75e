// The attributes a consumer of points asks a reader for, by the model's names
// (PointCloud::attributeNames(): "x", "red", "intensity", "gps_time", ...). Readers that can skip
// work for an attribute nobody asked for (LAZ of formats 6-10 and COPC: a layer never read) do,
// and leave its column out; others may fill every column. Positions are always read.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/column_names.h"

namespace parallax {

class AttributeSelection {
 public:
  // Every attribute (the default: what `convert` and the whole-file readers ask for).
  AttributeSelection() = default;
  // Only these (and the positions). "red", "green" or "blue" asks for the colour.
  static AttributeSelection only(std::vector<std::string> names) {
    AttributeSelection selection;
    selection.all_ = false;
    selection.names_ = std::move(names);
    return selection;
  }

  bool all() const { return all_; }
  const std::vector<std::string>& names() const { return names_; }

  bool wants(std::string_view name) const {
    if (all_ || name == column_names::kX || name == column_names::kY || name == column_names::kZ) {
      return true;
    }
    const bool colour =
        name == column_names::kRed || name == column_names::kGreen || name == column_names::kBlue;
    return std::any_of(names_.begin(), names_.end(), [&](const std::string& n) {
      return n == name || (colour && (n == column_names::kRed || n == column_names::kGreen ||
                                      n == column_names::kBlue));
    });
  }
  bool wantsColor() const { return wants(column_names::kRed); }

  // Adds `name` (no effect when every attribute is selected).
  void add(std::string name) {
    if (!all_ && !wants(name)) names_.push_back(std::move(name));
  }

 private:
  bool all_ = true;
  std::vector<std::string> names_;
};

}  // namespace parallax
