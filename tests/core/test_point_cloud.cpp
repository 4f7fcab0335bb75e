#include "core/point_cloud.h"

#include <gtest/gtest.h>

namespace parallax {
namespace {

PointCloud makeCloud() {
  PointCloud cloud;
  cloud.count = 3;
  cloud.quantization.scale = {0.5, 0.25, 1.0};
  cloud.quantization.offset = {100.0, -5.0, 0.0};
  cloud.positions = Column<Int3>(3);
  cloud.positions[0] = {0, 0, 0};
  cloud.positions[1] = {-4, 8, 3};
  cloud.positions[2] = {10, -2, -7};
  cloud.colors = Column<Rgba8>(3);
  ScalarColumn extra{"confidence", ScalarType::UInt16, ByteBuffer(3 * 2)};
  extra.as<std::uint16_t>()[0] = 1;
  extra.as<std::uint16_t>()[1] = 65535;
  extra.as<std::uint16_t>()[2] = 7;
  cloud.scalars.push_back(std::move(extra));
  return cloud;
}

TEST(PointCloud, BoundsAreComputedInWorldCoordinates) {
  PointCloud cloud = makeCloud();
  cloud.computeBounds();
  EXPECT_EQ(cloud.bounds.min, (std::array<double, 3>{98.0, -5.5, -7.0}));
  EXPECT_EQ(cloud.bounds.max, (std::array<double, 3>{105.0, -3.0, 3.0}));
}

TEST(PointCloud, EmptyCloudHasEmptyBounds) {
  PointCloud cloud;
  cloud.computeBounds();
  EXPECT_TRUE(cloud.bounds.empty());
}

TEST(PointCloud, AttributeNamesListPresentColumnsInOrder) {
  PointCloud cloud = makeCloud();
  EXPECT_EQ(cloud.attributeNames(),
            (std::vector<std::string>{"x", "y", "z", "red", "green", "blue", "confidence"}));
  EXPECT_NE(cloud.findScalar("confidence"), nullptr);
  EXPECT_EQ(cloud.findScalar("missing"), nullptr);
  EXPECT_EQ(cloud.findScalar("confidence")->valueAsDouble(1), 65535.0);
}

TEST(PointCloud, CloneIsDeep) {
  PointCloud cloud = makeCloud();
  PointCloud copy = cloud.clone();
  copy.positions[1].x = 99;
  copy.scalars[0].as<std::uint16_t>()[0] = 42;
  EXPECT_EQ(cloud.positions[1].x, -4);
  EXPECT_EQ(cloud.scalars[0].as<std::uint16_t>()[0], 1);
  EXPECT_EQ(copy.worldX(1), 99 * 0.5 + 100.0);
}

TEST(Column, LargeColumnsAreWritableAndMovable) {
  Column<float> big((std::size_t{8} << 20) / sizeof(float));  // above the mmap threshold
  big[0] = 1.0f;
  big[big.size() - 1] = 2.0f;
  Column<float> moved = std::move(big);
  EXPECT_EQ(moved[0], 1.0f);
  EXPECT_EQ(moved[moved.size() - 1], 2.0f);
  EXPECT_TRUE(big.empty());  // NOLINT(bugprone-use-after-move): the moved-from state is specified
}

}  // namespace
}  // namespace parallax
