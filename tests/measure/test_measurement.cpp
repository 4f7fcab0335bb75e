// Measurement arithmetic in double on shapes whose answers are known exactly.
#include "measure/measurement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace parallax {
namespace {

// A UTM-sized origin: every test shape is placed there, where a float is good to 6 cm only.
constexpr double kEast = 500000.0, kNorth = 5000000.0, kHeight = 100.0;

glm::dvec3 utm(double x, double y, double z) {
  return {kEast + x, kNorth + y, kHeight + z};
}

TEST(MeasurementArithmetic, UnitSquareAtUtmHasExactAreas) {
  const std::vector<glm::dvec3> square{utm(0, 0, 0), utm(1, 0, 0), utm(1, 1, 0), utm(0, 1, 0)};
  EXPECT_EQ(polygonArea3d(square), 1.0);
  EXPECT_EQ(polygonAreaProjected(square), 1.0);
  EXPECT_EQ(polygonPerimeter(square), 4.0);
  // Clockwise gives the same (unsigned) areas.
  const std::vector<glm::dvec3> clockwise(square.rbegin(), square.rend());
  EXPECT_EQ(polygonArea3d(clockwise), 1.0);
  EXPECT_EQ(polygonAreaProjected(clockwise), 1.0);
}

TEST(MeasurementArithmetic, MillimetreSquareAtUtmKeepsItsArea) {
  // 1 mm x 1 mm at 500 km: products of absolute coordinates would cancel every digit of it.
  const double mm = 0.001;
  const std::vector<glm::dvec3> square{utm(0, 0, 0), utm(mm, 0, 0), utm(mm, mm, 0), utm(0, mm, 0)};
  // The sides as the doubles hold them (500000.001 is not exactly 0.001 from 500000; the
  // subtraction of such close values is exact): the area is their product, to the last bits.
  const double dx = square[1].x - square[0].x, dy = square[2].y - square[1].y;
  EXPECT_NEAR(dx, mm, 1e-9);
  EXPECT_DOUBLE_EQ(polygonArea3d(square), dx * dy);
  EXPECT_DOUBLE_EQ(polygonAreaProjected(square), dx * dy);
}

TEST(MeasurementArithmetic, TiltedSquareAreasDifferByCosine) {
  const double theta = 30.0 * std::numbers::pi / 180.0;
  const double c = std::cos(theta), s = std::sin(theta);
  // A 2 x 3 rectangle tilted by 30 degrees about the x axis.
  const std::vector<glm::dvec3> tilted{utm(0, 0, 0), utm(2, 0, 0), utm(2, 3 * c, 3 * s),
                                       utm(0, 3 * c, 3 * s)};
  EXPECT_NEAR(polygonArea3d(tilted), 6.0, 1e-9);
  EXPECT_NEAR(polygonAreaProjected(tilted), 6.0 * c, 1e-9);
  // (The UTM coordinates round the tilted corners to about 1e-9: the ratio holds to that.)
  EXPECT_NEAR(polygonAreaProjected(tilted) / polygonArea3d(tilted), c, 1e-9);
  // At the origin, where the corners are exact to 1e-16, it holds to the last bits.
  const std::vector<glm::dvec3> local{{0, 0, 0}, {2, 0, 0}, {2, 3 * c, 3 * s}, {0, 3 * c, 3 * s}};
  EXPECT_NEAR(polygonAreaProjected(local) / polygonArea3d(local), c, 1e-15);
}

TEST(MeasurementArithmetic, NonPlanarPolygonUsesNewellArea) {
  // A saddle: its projections on the yz and zx planes are bow ties of signed area 0, so
  // Newell's vector is (0, 0, 1): the 3D area is the area on its best-fit plane, 1.
  const std::vector<glm::dvec3> saddle{utm(0, 0, 0), utm(1, 0, 1), utm(1, 1, 0), utm(0, 1, 1)};
  EXPECT_NEAR(polygonArea3d(saddle), 1.0, 1e-12);
  EXPECT_EQ(polygonAreaProjected(saddle), 1.0);
}

TEST(MeasurementArithmetic, ThreeFourFiveTriangle) {
  Measurement m{.kind = MeasurementKind::Area,
                .points = {utm(0, 0, 0), utm(3, 0, 0), utm(3, 4, 0)}};
  const MeasurementValues v = measurementValues(m);
  EXPECT_EQ(v.area_3d, 6.0);
  EXPECT_EQ(v.area_projected, 6.0);
  EXPECT_EQ(v.total, 12.0);
  ASSERT_EQ(v.segments.size(), 3u);
  EXPECT_EQ(v.segments[0], 3.0);
  EXPECT_EQ(v.segments[1], 4.0);
  EXPECT_EQ(v.segments[2], 5.0);
  EXPECT_NEAR(angleDegrees(utm(0, 0, 0), utm(3, 0, 0), utm(3, 4, 0)), 90.0, 1e-12);
  EXPECT_NEAR(angleDegrees(utm(3, 0, 0), utm(0, 0, 0), utm(3, 4, 0)),
              std::atan2(4.0, 3.0) * 180.0 / std::numbers::pi, 1e-12);
}

TEST(MeasurementArithmetic, DistancePolylineSegmentsAndTotal) {
  Measurement m{.kind = MeasurementKind::Distance,
                .points = {utm(0, 0, 0), utm(3, 4, 0), utm(3, 4, 12), utm(3, 4, 12)}};
  const MeasurementValues v = measurementValues(m);
  ASSERT_EQ(v.segments.size(), 3u);
  EXPECT_EQ(v.segments[0], 5.0);
  EXPECT_EQ(v.segments[1], 12.0);
  EXPECT_EQ(v.segments[2], 0.0);
  EXPECT_EQ(v.total, 17.0);
  EXPECT_EQ(v.horizontal, 5.0);
  EXPECT_EQ(v.dz, 12.0);
  EXPECT_EQ(describeMeasurement(m), "distance 17.000 m (4 points)");
}

TEST(MeasurementArithmetic, HeightDifferenceIsSigned) {
  Measurement m{.kind = MeasurementKind::Height, .points = {utm(0, 0, 7.5), utm(6, 8, 2.25)}};
  const MeasurementValues v = measurementValues(m);
  EXPECT_EQ(v.dz, -5.25);
  EXPECT_EQ(v.horizontal, 10.0);
  EXPECT_DOUBLE_EQ(v.total, std::sqrt(100.0 + 5.25 * 5.25));
}

TEST(MeasurementArithmetic, AnglesAtTheMiddleVertex) {
  EXPECT_NEAR(angleDegrees(utm(1, 0, 0), utm(0, 0, 0), utm(0, 0, 1)), 90.0, 1e-12);
  EXPECT_NEAR(angleDegrees(utm(1, 0, 0), utm(0, 0, 0), utm(1, 1, 0)), 45.0, 1e-12);
  EXPECT_NEAR(angleDegrees(utm(1, 0, 0), utm(0, 0, 0), utm(-1, 0, 0)), 180.0, 1e-12);
  // Nearly collinear: atan2 keeps the tiny angle that acos of a dot product would lose.
  EXPECT_NEAR(angleDegrees({1, 0, 0}, {0, 0, 0}, {1, 1e-9, 0}), 1e-9 * 180.0 / std::numbers::pi,
              1e-20);
  EXPECT_EQ(angleDegrees(utm(0, 0, 0), utm(0, 0, 0), utm(1, 0, 0)), 0.0);
}

TEST(MeasurementArithmetic, GrowingMeasurementsGiveZerosNotGarbage) {
  for (MeasurementKind kind : {MeasurementKind::Distance, MeasurementKind::Area,
                               MeasurementKind::Angle, MeasurementKind::Height}) {
    Measurement m{.kind = kind, .points = {utm(0, 0, 0)}};
    const MeasurementValues v = measurementValues(m);
    EXPECT_EQ(v.total, 0.0);
    EXPECT_EQ(v.area_3d, 0.0);
    EXPECT_EQ(v.angle_deg, 0.0);
    EXPECT_TRUE(v.segments.empty());
  }
}

TEST(MeasurementArithmetic, LabelsSitOnSegmentsAndVertices) {
  Measurement m{.kind = MeasurementKind::Distance,
                .name = "ridge",
                .points = {utm(0, 0, 0), utm(3, 4, 0), utm(3, 4, 12)}};
  const auto labels = measurementLabels(m, 2);
  ASSERT_EQ(labels.size(), 3u);
  EXPECT_EQ(labels[0].anchor, utm(1.5, 2, 0));
  EXPECT_EQ(labels[0].text, "5.00 m");
  EXPECT_EQ(labels[1].text, "12.00 m");
  EXPECT_EQ(labels[2].anchor, utm(3, 4, 12));
  EXPECT_EQ(labels[2].text, "ridge: total 17.00 m");
}

TEST(MeasurementArithmetic, KindNamesRoundTrip) {
  for (MeasurementKind kind :
       {MeasurementKind::Point, MeasurementKind::Distance, MeasurementKind::Height,
        MeasurementKind::Area, MeasurementKind::Angle, MeasurementKind::Profile}) {
    EXPECT_EQ(measurementKindFromName(measurementKindName(kind)), kind);
  }
  EXPECT_FALSE(measurementKindFromName("Distance"));
  EXPECT_FALSE(measurementKindFromName(""));
}

}  // namespace
}  // namespace parallax
