// The point filter on the CPU (what `convert` applies) and the ASPRS class names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "core/classification.h"
#include "core/point_filter.h"

namespace parallax::test {
namespace {

// Five points on the x axis at 0..4 m, classes 0..4, with a colour and a scalar to carry.
PointCloud fivePoints(bool classified) {
  PointCloud cloud;
  cloud.count = 5;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.quantization.offset = {500000.0, 5000000.0, 0.0};
  cloud.positions = Column<Int3>(5);
  cloud.colors = Column<Rgba8>(5);
  if (classified) cloud.classification = Column<std::uint8_t>(5);
  ScalarColumn gps{.name = "gps_time", .type = ScalarType::Float64, .data = ByteBuffer(5 * 8)};
  for (int i = 0; i < 5; ++i) {
    cloud.positions[std::size_t(i)] = {1000 * i, 0, 0};
    cloud.colors[std::size_t(i)] = {std::uint8_t(i), 0, 0, 255};
    if (classified) cloud.classification[std::size_t(i)] = std::uint8_t(i);
    gps.as<double>()[i] = 10.0 + i;
  }
  cloud.scalars.push_back(std::move(gps));
  cloud.computeBounds();
  return cloud;
}

TEST(PointFilter, DefaultKeepsAllAndSettingAClassOrBoxDoesNot) {
  PointFilter filter;
  EXPECT_TRUE(filter.keepsAll());
  filter.setClass(200, false);
  EXPECT_FALSE(filter.keepsAll());
  EXPECT_FALSE(filter.keepsClass(200));
  EXPECT_TRUE(filter.keepsClass(199));
  filter.setClass(200, true);
  EXPECT_TRUE(filter.keepsAll());
  Bounds3 box;
  box.extend(0, 0, 0);
  filter.setClipBox(box, false);
  EXPECT_FALSE(filter.keepsAll());
}

TEST(PointFilter, ClipBoxInsideAndOutsideIncludeTheFaces) {
  Bounds3 box;
  box.extend(500001.0, 4999999.0, -1.0);
  box.extend(500003.0, 5000001.0, 1.0);
  PointFilter filter;
  filter.setClipBox(box, false);
  EXPECT_TRUE(filter.keepsPosition(500001.0, 5000000.0, 0.0));  // on a face
  EXPECT_TRUE(filter.keepsPosition(500003.0, 5000001.0, 1.0));  // a corner
  EXPECT_FALSE(filter.keepsPosition(500003.0005, 5000000.0, 0.0));
  filter.setClipBox(box, true);
  EXPECT_FALSE(filter.keepsPosition(500002.0, 5000000.0, 0.0));
  EXPECT_TRUE(filter.keepsPosition(500000.9995, 5000000.0, 0.0));
  ASSERT_TRUE(filter.clipBox().has_value());
  EXPECT_EQ(filter.clipBox()->box, box);  // unturned: exactly the box given
  EXPECT_EQ(filter.clipBox()->yaw_degrees, 0.0);
  filter.clip_planes.pop_back();
  EXPECT_FALSE(filter.clipBox().has_value());
}

// A long thin box (20 m by 2 m) at UTM coordinates turned by 90 degrees covers what an unturned
// 2 m by 20 m box would; turned by 30 degrees, its corners are where the rotation puts them.
TEST(PointFilter, TurnedClipBoxTurnsAboutItsCentre) {
  const double cx = 500123.5, cy = 5000456.5;
  Bounds3 box;
  box.extend(cx - 10.0, cy - 1.0, 99.0);
  box.extend(cx + 10.0, cy + 1.0, 101.0);
  PointFilter filter;
  filter.setClipBox(box, false, 90.0);
  EXPECT_TRUE(filter.keepsPosition(cx, cy + 9.9, 100.0));
  EXPECT_TRUE(filter.keepsPosition(cx + 0.9, cy - 9.9, 100.0));
  EXPECT_FALSE(filter.keepsPosition(cx + 9.0, cy, 100.0));  // inside the box before it turned
  EXPECT_FALSE(filter.keepsPosition(cx, cy + 10.001, 100.0));
  EXPECT_FALSE(filter.keepsPosition(cx, cy, 101.001));  // z is not turned
  filter.setClipBox(box, false, 30.0);
  const double cs = std::cos(std::numbers::pi / 6.0), sn = std::sin(std::numbers::pi / 6.0);
  // Points at the box's own coordinates (u, v), a millimetre inside or outside a face.
  const auto at = [&](double u, double v) {
    return filter.keepsPosition(cx + cs * u - sn * v, cy + sn * u + cs * v, 100.0);
  };
  EXPECT_TRUE(at(9.999, 0.999));
  EXPECT_TRUE(at(-9.999, -0.999));
  EXPECT_FALSE(at(10.001, 0.0));
  EXPECT_FALSE(at(0.0, -1.001));
  EXPECT_FALSE(filter.keepsPosition(cx + 9.999, cy + 0.999, 100.0));  // the unturned corner
  filter.setClipBox(box, true, 30.0);
  EXPECT_FALSE(at(9.999, 0.999));
  EXPECT_TRUE(at(10.001, 0.0));
  // The footprint's corners (the viewer's outline) where the same rotation puts them.
  const auto corners = ClipBox{box, 30.0}.corners();
  const double expected[4][2] = {{-10, -1}, {10, -1}, {10, 1}, {-10, 1}};
  for (std::size_t i = 0; i < 4; ++i) {
    const double u = expected[i][0], v = expected[i][1];
    EXPECT_NEAR(corners[i][0], cx + cs * u - sn * v, 1e-9) << i;
    EXPECT_NEAR(corners[i][1], cy + sn * u + cs * v, 1e-9) << i;
  }
}

TEST(PointFilter, TurnedClipBoxComesBackFromItsPlanes) {
  Bounds3 box;
  box.extend(500100.25, 5000200.5, -3.0);
  box.extend(500130.75, 5000210.0, 12.5);
  for (const double yaw : {30.0, -135.0, 90.0, 180.0, 1e-9}) {
    PointFilter filter;
    filter.setClipBox(box, false, yaw);
    const std::optional<ClipBox> back = filter.clipBox();
    ASSERT_TRUE(back.has_value()) << yaw;
    EXPECT_NEAR(back->yaw_degrees, yaw, 1e-9) << yaw;
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_NEAR(back->box.min[a], box.min[a], 1e-8) << yaw << " axis " << a;
      EXPECT_NEAR(back->box.max[a], box.max[a], 1e-8) << yaw << " axis " << a;
    }
  }
  // Six planes that are not a box (two faces not opposite) are not shown as one.
  PointFilter filter;
  filter.setClipBox(box, false, 30.0);
  filter.clip_planes[1] = {0, -1, 0, 5000210.0};
  EXPECT_FALSE(filter.clipBox().has_value());
}

TEST(PointFilter, FilterPointsCarriesEveryColumn) {
  PointFilter filter;
  filter.keepOnlyClasses({1, 3, 4});
  Bounds3 box;
  box.extend(500000.5, -1e9, -1.0);
  box.extend(500003.5, 1e9, 1.0);
  filter.setClipBox(box, false);
  const PointCloud kept = filterPoints(fivePoints(true), filter);
  ASSERT_EQ(kept.count, 2u);  // classes 1 and 3 (4 is outside the box, 0 and 2 not listed)
  EXPECT_EQ(kept.positions[0].x, 1000);
  EXPECT_EQ(kept.positions[1].x, 3000);
  EXPECT_EQ(kept.colors[1].r, 3);
  EXPECT_EQ(kept.classification[0], 1);
  ASSERT_EQ(kept.scalars.size(), 1u);
  EXPECT_EQ(kept.scalars[0].as<double>()[1], 13.0);
  EXPECT_EQ(kept.bounds.min[0], 500001.0);
  EXPECT_EQ(kept.bounds.max[0], 500003.0);
}

TEST(PointFilter, WithoutClassificationEveryPointIsClassZero) {
  PointFilter filter;
  filter.keepOnlyClasses({1, 2});
  EXPECT_EQ(filterPoints(fivePoints(false), filter).count, 0u);
  filter.keepOnlyClasses({0});
  EXPECT_EQ(filterPoints(fivePoints(false), filter).count, 5u);
}

// Eight returns of one cloud: (r, n) pairs covering first, last, intermediate and single.
PointCloud returnsCloud(bool with_returns) {
  PointCloud cloud;
  const int pairs[8][2] = {{1, 1}, {1, 3}, {2, 3}, {3, 3}, {1, 2}, {2, 2}, {5, 7}, {17, 20}};
  cloud.count = 8;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.positions = Column<Int3>(8);
  cloud.intensity = Column<float>(8);
  ScalarColumn r{.name = "return_number", .type = ScalarType::UInt8, .data = ByteBuffer(8)};
  ScalarColumn n{.name = "number_of_returns", .type = ScalarType::UInt8, .data = ByteBuffer(8)};
  ScalarColumn gps{.name = "gps_time", .type = ScalarType::Float64, .data = ByteBuffer(8 * 8)};
  for (int i = 0; i < 8; ++i) {
    cloud.positions[std::size_t(i)] = {1000 * i, 0, 500 * i};  // z 0, 0.5, ... 3.5 m
    cloud.intensity[std::size_t(i)] = float(100 * i);
    r.as<std::uint8_t>()[i] = std::uint8_t(pairs[i][0]);
    n.as<std::uint8_t>()[i] = std::uint8_t(pairs[i][1]);
    gps.as<double>()[i] = 400000000.0 + 0.000001 * i;  // a microsecond apart
  }
  if (with_returns) cloud.scalars.push_back(std::move(r)), cloud.scalars.push_back(std::move(n));
  cloud.scalars.push_back(std::move(gps));
  cloud.computeBounds();
  return cloud;
}

// The x (in metres) of the kept points: which ones, in order.
std::vector<int> keptIndices(const PointCloud& cloud, const PointFilter& filter) {
  const PointCloud kept = filterPoints(cloud, filter);
  std::vector<int> indices;
  for (std::size_t i = 0; i < kept.count; ++i) indices.push_back(kept.positions[i].x / 1000);
  return indices;
}

TEST(PointFilter, ReturnKindsAndNumbers) {
  const PointCloud cloud = returnsCloud(true);
  PointFilter filter;
  EXPECT_TRUE(filter.keepsEveryReturn());
  filter.keepOnlyReturns({ReturnKind::First}, {});
  EXPECT_FALSE(filter.keepsAll());
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{0, 1, 4}));
  filter.keepOnlyReturns({ReturnKind::Last}, {});
  // 17 of 20 counts as 15 of 15: the last.
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{0, 3, 5, 7}));
  filter.keepOnlyReturns({ReturnKind::Intermediate}, {});
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{2, 6}));
  filter.keepOnlyReturns({ReturnKind::Single}, {});
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{0}));
  filter.keepOnlyReturns({ReturnKind::Multiple}, {});
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  filter.keepOnlyReturns({ReturnKind::Single}, {2, 5});
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{0, 2, 5, 6}));
}

TEST(PointFilter, WithoutReturnsEveryPointIsReturnOneOfOne) {
  const PointCloud cloud = returnsCloud(false);
  PointFilter filter;
  filter.keepOnlyReturns({ReturnKind::Intermediate}, {2});
  EXPECT_EQ(filterPoints(cloud, filter).count, 0u);
  filter.keepOnlyReturns({ReturnKind::First, ReturnKind::Single}, {});
  EXPECT_EQ(filterPoints(cloud, filter).count, 8u);
}

TEST(PointFilter, IntensityElevationAndGpsTimeRangesAreInclusive) {
  const PointCloud cloud = returnsCloud(true);
  PointFilter filter;
  filter.intensity = ValueRange{100.0, 300.0};
  EXPECT_FALSE(filter.keepsAll());
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{1, 2, 3}));
  filter.elevation = ValueRange{1.0, 3.5};  // z = 0.5 i
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{2, 3}));
  filter = {};
  // A microsecond apart at 4e8 s: a float could not tell them apart.
  filter.gps_time = ValueRange{400000000.0000015, 400000000.0000045};
  EXPECT_EQ(keptIndices(cloud, filter), (std::vector<int>{2, 3, 4}));
}

TEST(PointFilter, MissingIntensityAndGpsTimeAreZero) {
  PointCloud cloud = fivePoints(true);
  cloud.scalars.clear();
  PointFilter filter;
  filter.intensity = ValueRange{0.0, 10.0};
  filter.gps_time = ValueRange{-1.0, 0.0};
  EXPECT_EQ(filterPoints(cloud, filter).count, 5u);
  filter.gps_time = ValueRange{1.0, 2.0};
  EXPECT_EQ(filterPoints(cloud, filter).count, 0u);
}

TEST(PointFilter, PolygonInsideOutsideAndWithABox) {
  PointFilter filter;
  // An L: the unit squares (0..2, 0..1) and (0..1, 1..2).
  filter.polygon = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_FALSE(filter.keepsAll());
  EXPECT_TRUE(filter.keepsPosition(0.5, 0.5, 100.0));  // any z
  EXPECT_TRUE(filter.keepsPosition(1.5, 0.5, -100.0));
  EXPECT_TRUE(filter.keepsPosition(0.5, 1.5, 0.0));
  EXPECT_FALSE(filter.keepsPosition(1.5, 1.5, 0.0));  // the notch
  EXPECT_FALSE(filter.keepsPosition(-0.5, 0.5, 0.0));
  filter.clip_outside = true;
  EXPECT_FALSE(filter.keepsPosition(0.5, 0.5, 0.0));
  EXPECT_TRUE(filter.keepsPosition(1.5, 1.5, 0.0));
  // A box bounds the polygon in z: the region is their intersection.
  Bounds3 box;
  box.extend(-10, -10, 0);
  box.extend(10, 10, 1);
  filter.setClipBox(box, false);
  EXPECT_TRUE(filter.keepsPosition(0.5, 0.5, 0.5));
  EXPECT_FALSE(filter.keepsPosition(0.5, 0.5, 1.5));
  EXPECT_FALSE(filter.keepsPosition(1.5, 1.5, 0.5));
  // Highlighted, the region keeps everything and only says what is in it.
  filter.clip_highlight = true;
  EXPECT_TRUE(filter.keepsPosition(1.5, 1.5, 0.5));
  EXPECT_TRUE(filter.keepsPosition(0.5, 0.5, 0.5));
  EXPECT_FALSE(filter.inRegion(1.5, 1.5, 0.5));
  EXPECT_TRUE(filter.inRegion(0.5, 0.5, 0.5));
}

TEST(Classification, AsprsNamesAndNumbersForTheRest) {
  EXPECT_EQ(classLabel(0), "never classified");
  EXPECT_EQ(classLabel(2), "ground");
  EXPECT_EQ(classLabel(7), "low point (noise)");
  EXPECT_EQ(classLabel(8), "class 8");
  EXPECT_EQ(classLabel(9), "water");
  EXPECT_EQ(classLabel(12), "class 12");
  EXPECT_EQ(classLabel(18), "high noise");
  EXPECT_EQ(classLabel(19), "class 19");
  EXPECT_EQ(classLabel(255), "class 255");
}

}  // namespace
}  // namespace parallax::test
