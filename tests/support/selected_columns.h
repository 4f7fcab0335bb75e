// What the selective-reading tests share: the selections tried, and the check that a read asked
// for some attributes holds exactly a full read's columns for those and no others.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/point_cloud.h"

namespace parallax::test {

inline std::vector<AttributeSelection> selections() {
  return {AttributeSelection::only({}),
          AttributeSelection::only({"red"}),
          AttributeSelection::only({"intensity"}),
          AttributeSelection::only({"classification"}),
          AttributeSelection::only({"gps_time"}),
          AttributeSelection::only({"user_data", "point_source_id", "scan_angle"}),
          AttributeSelection::only({"return_number", "nir"}),
          AttributeSelection::only({"red", "intensity", "classification"}),
          AttributeSelection{}};
}

inline std::string describe(const AttributeSelection& s) {
  if (s.all()) return "all";
  std::string text = "x y z";
  for (const std::string& name : s.names()) text += " " + name;
  return text;
}

template <class T>
inline bool sameColumn(const Column<T>& a, const Column<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// `part` holds exactly the columns of `full` that `selection` asks for, with the same values.
inline void expectSelected(const PointCloud& full, const PointCloud& part,
                           const AttributeSelection& selection, const std::string& what) {
  SCOPED_TRACE(what + ", asked: " + describe(selection));
  ASSERT_EQ(part.count, full.count);
  EXPECT_TRUE(sameColumn(part.positions, full.positions));
  EXPECT_EQ(part.bounds.min, full.bounds.min);
  EXPECT_EQ(part.bounds.max, full.bounds.max);
  const bool colour = selection.wantsColor() && full.hasColors();
  EXPECT_EQ(part.hasColors(), colour);
  EXPECT_EQ(part.hasStoredColors(), colour && full.hasStoredColors());
  if (part.hasColors()) {
    EXPECT_TRUE(sameColumn(part.colors, full.colors));
    EXPECT_TRUE(sameColumn(part.stored_colors, full.stored_colors));
  }
  EXPECT_EQ(part.hasIntensity(), selection.wants("intensity") && full.hasIntensity());
  if (part.hasIntensity()) {
    EXPECT_TRUE(sameColumn(part.intensity, full.intensity));
  }
  EXPECT_EQ(part.hasClassification(),
            selection.wants("classification") && full.hasClassification());
  if (part.hasClassification()) {
    EXPECT_TRUE(sameColumn(part.classification, full.classification));
  }
  std::size_t expected_scalars = 0;
  for (const ScalarColumn& column : full.scalars) {
    const ScalarColumn* found = part.findScalar(column.name);
    if (!selection.wants(column.name)) {
      EXPECT_EQ(found, nullptr) << column.name << " was not asked for";
      continue;
    }
    ++expected_scalars;
    ASSERT_NE(found, nullptr) << column.name;
    EXPECT_EQ(found->type, column.type) << column.name;
    EXPECT_TRUE(found->data.size() == column.data.size() &&
                std::memcmp(found->data.data(), column.data.data(), column.data.size()) == 0)
        << column.name;
  }
  EXPECT_EQ(part.scalars.size(), expected_scalars);
}

}  // namespace parallax::test
