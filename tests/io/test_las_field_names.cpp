#include "io/las_field_names.h"

#include <gtest/gtest.h>

#include <string>

#include "core/column_names.h"

namespace parallax {
namespace {

TEST(LasFieldNames, EveryToolsSpellingOfAFieldIsThatField) {
  for (const char* name : {"gps_time", "GpsTime", "GPS Time", "scalar_GpsTime", "gps-time"}) {
    EXPECT_EQ(lasFieldNamed(name), LasField::GpsTime) << name;
  }
  EXPECT_EQ(lasFieldNamed("ClassFlags"), LasField::ClassFlags);
  EXPECT_EQ(lasFieldNamed("ScanChannel"), LasField::Channel);
  EXPECT_EQ(lasFieldNamed("Infrared"), LasField::Nir);
  EXPECT_EQ(lasFieldNamed("NearInfrared"), LasField::Nir);
  EXPECT_EQ(lasFieldNamed("Withheld"), LasField::Withheld);
  EXPECT_EQ(lasFieldNamed("height_above_ground"), LasField::None);
  EXPECT_EQ(lasFieldNamed("gps_time_2"), LasField::None);
}

// A field's model column is a name that lasFieldNamed maps back to that field: the reader's
// column and the writer's field agree both ways.
TEST(LasFieldNames, AFieldsColumnNamesThatField) {
  for (int i = 1; i <= int(LasField::WaveDz); ++i) {
    const LasField field = LasField(i);
    const char* column = lasFieldColumn(field);
    if (column == nullptr) continue;
    EXPECT_EQ(lasFieldNamed(column), field) << column;
  }
  EXPECT_STREQ(lasFieldColumn(LasField::GpsTime), column_names::kGpsTime);
  EXPECT_STREQ(lasFieldColumn(LasField::WaveDz), column_names::kWaveformDz);
  EXPECT_EQ(lasFieldColumn(LasField::Synthetic), nullptr);
  EXPECT_EQ(lasFieldColumn(LasField::None), nullptr);
}

}  // namespace
}  // namespace parallax
