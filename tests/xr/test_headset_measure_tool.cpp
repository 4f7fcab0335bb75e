// The headset's measurement tools (xr/headset_measure_tool.h): which picks make which measurement,
// and what the tool button does. The values themselves are measure/'s (tests/measure).
#include "xr/headset_measure_tool.h"

#include <gtest/gtest.h>

#include <cmath>

#include "xr/locomotion.h"

namespace parallax {
namespace {

const glm::dvec3 kA{512345.25, 5412345.75, 312.5}, kB{512350.0, 5412349.5, 314.25},
    kC{512339.125, 5412355.0, 310.0};

TEST(HeadsetMeasureTool, ADistanceFinishesAtItsSecondPick) {
  HeadsetMeasureTool tool;
  EXPECT_EQ(tool.kind(), MeasurementKind::Distance);
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_EQ(tool.inProgress().points, std::vector<glm::dvec3>{kA});
  const auto done = tool.pick(kB);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->kind, MeasurementKind::Distance);
  EXPECT_EQ(done->points, (std::vector<glm::dvec3>{kA, kB}));
  EXPECT_TRUE(tool.inProgress().points.empty());
  EXPECT_EQ(tool.kind(), MeasurementKind::Distance) << "the tool stays";
}

TEST(HeadsetMeasureTool, TheButtonCyclesInTheWindowsOrderAndDropsWhatIsInProgress) {
  HeadsetMeasureTool tool;
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Height);
  EXPECT_TRUE(tool.inProgress().points.empty());
  EXPECT_EQ(tool.inProgress().kind, MeasurementKind::Height);
  EXPECT_FALSE(tool.pick(kB));
  const auto height = tool.pick(kA);
  ASSERT_TRUE(height);
  EXPECT_EQ(height->kind, MeasurementKind::Height);
  EXPECT_EQ(height->points, (std::vector<glm::dvec3>{kB, kA}));
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Area);
  // An area of two points cannot be closed: the button moves on to the angle tool.
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_FALSE(tool.pick(kB));
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Angle);
  EXPECT_TRUE(tool.inProgress().points.empty());
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Profile);
  EXPECT_TRUE(tool.inProgress().points.empty());
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Point);
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Distance);
}

// An angle at its third pick (the vertex the second), a profile's section line at its second
// with view's corridor width, a point at once.
TEST(HeadsetMeasureTool, AnglesProfilesAndPointsFinishAtTheirPicks) {
  HeadsetMeasureTool tool(2.5);
  for (int i = 0; i < 3; ++i) tool.toolButton();
  ASSERT_EQ(tool.kind(), MeasurementKind::Angle);
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_FALSE(tool.pick(kB));
  const auto angle = tool.pick(kC);
  ASSERT_TRUE(angle);
  EXPECT_EQ(angle->kind, MeasurementKind::Angle);
  EXPECT_EQ(angle->points, (std::vector<glm::dvec3>{kA, kB, kC}));
  tool.toolButton();
  ASSERT_EQ(tool.kind(), MeasurementKind::Profile);
  EXPECT_FALSE(tool.pick(kC));
  const auto profile = tool.pick(kA);
  ASSERT_TRUE(profile);
  EXPECT_EQ(profile->kind, MeasurementKind::Profile);
  EXPECT_EQ(profile->points, (std::vector<glm::dvec3>{kC, kA}));
  EXPECT_EQ(profile->profile_width, 2.5);
  tool.toolButton();
  ASSERT_EQ(tool.kind(), MeasurementKind::Point);
  const auto point = tool.pick(kB);
  ASSERT_TRUE(point);
  EXPECT_EQ(point->kind, MeasurementKind::Point);
  EXPECT_EQ(point->points, std::vector<glm::dvec3>{kB});
  EXPECT_TRUE(tool.inProgress().points.empty());
  EXPECT_EQ(tool.kind(), MeasurementKind::Point) << "the tool stays";
}

TEST(HeadsetMeasureTool, AnAreaTakesEveryPickUntilTheButtonClosesIt) {
  HeadsetMeasureTool tool;
  tool.toolButton();
  tool.toolButton();
  ASSERT_EQ(tool.kind(), MeasurementKind::Area);
  for (const glm::dvec3& p : {kA, kB, kC, kA + glm::dvec3(1, 0, 0)}) EXPECT_FALSE(tool.pick(p));
  const auto area = tool.toolButton();
  ASSERT_TRUE(area);
  EXPECT_EQ(area->kind, MeasurementKind::Area);
  EXPECT_EQ(area->points.size(), 4u);
  EXPECT_EQ(tool.kind(), MeasurementKind::Area) << "closing an area keeps the tool";
  EXPECT_TRUE(tool.inProgress().points.empty());
}

// The secondary button (B, or Y) is a short press, one tool event at its release.
TEST(HeadsetMeasureTool, TheSecondaryButtonIsOneEventAPressAtItsRelease) {
  Locomotion locomotion(StagePlacement{});
  XrInput input;
  input.hands[kRightHand].tracked = true;
  input.hands[kRightHand].secondary = true;
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = false;
  EXPECT_TRUE(locomotion.update(input).tool[kRightHand]);
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = true;
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = false;
  const LocomotionEvents again = locomotion.update(input);
  EXPECT_TRUE(again.tool[kRightHand]);
  EXPECT_FALSE(again.tool[kLeftHand]);
  EXPECT_FALSE(again.pick[kRightHand]);
  EXPECT_FALSE(again.remove[kRightHand]);
}

// Held for kLongPressSeconds of display periods (0.5 s: four periods of 1/8 s after the frame it
// went down), it deletes once, and its release is no tool event.
TEST(HeadsetMeasureTool, TheSecondaryButtonHeldHalfASecondDeletesOnce) {
  Locomotion locomotion(StagePlacement{});
  XrInput input;
  input.period_s = 0.125;
  input.hands[kLeftHand].tracked = true;
  input.hands[kLeftHand].secondary = true;
  for (int frame = 0; frame < 4; ++frame) {
    const LocomotionEvents events = locomotion.update(input);
    EXPECT_FALSE(events.remove[kLeftHand]) << frame;
    EXPECT_FALSE(events.tool[kLeftHand]) << frame;
  }
  EXPECT_TRUE(locomotion.update(input).remove[kLeftHand]) << "held 4 x 0.125 s";
  for (int frame = 0; frame < 6; ++frame) EXPECT_FALSE(locomotion.update(input).remove[kLeftHand]);
  input.hands[kLeftHand].secondary = false;
  const LocomotionEvents released = locomotion.update(input);
  EXPECT_FALSE(released.tool[kLeftHand]) << "a long press is no tool event";
  EXPECT_FALSE(released.remove[kLeftHand]);
  // 45 frames at 90 Hz are half a second too, with the runtime's period in whole nanoseconds
  // (11 111 111 ns: 45 of them are 0.499999995 s).
  input.period_s = 11'111'111 * 1e-9;
  input.hands[kLeftHand].secondary = true;
  int deleted_at = -1;
  for (int frame = 0; frame <= 50; ++frame) {
    if (locomotion.update(input).remove[kLeftHand]) {
      EXPECT_EQ(deleted_at, -1);
      deleted_at = frame;
    }
  }
  EXPECT_EQ(deleted_at, 45);
}

// --- moving a vertex and deleting the measurement under the laser -----------------------------

// A laser from kA along file +y, and a point `depth` along it, off to its side (x) by the
// tangent of `deg` degrees: at exactly that angle from the ray.
const LaserRay kLaser{kA, {0.0, 1.0, 0.0}};
glm::dvec3 offRay(double depth, double deg) {
  return kA + glm::dvec3(depth * std::tan(glm::radians(deg)), depth, 0.0);
}

TEST(HeadsetMeasureTool, TheVertexUnderTheLaserIsTheOneAtTheLeastAngleWithinTheCone) {
  ASSERT_EQ(kVertexConeDeg, 0.5);
  std::vector<Measurement> list{
      {.kind = MeasurementKind::Distance, .points = {offRay(4.0, 0.3), offRay(9.0, 0.45)}},
      {.kind = MeasurementKind::Point, .points = {offRay(20.0, 0.2)}},
      {.kind = MeasurementKind::Height, .points = {offRay(2.0, 0.55), kA - glm::dvec3(0, 3, 0)}}};
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{1, 0})) << "0.2 degrees, the least";
  list[1].points[0] = offRay(20.0, 0.6);
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{0, 0})) << "0.3 degrees";
  list[0].points[0] = offRay(4.0, 0.51);
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{0, 1})) << "0.45 degrees";
  list[0].points[1] = offRay(9.0, 0.51);
  // Nothing within 0.5 degrees: 0.51, 0.51, 0.6, 0.55 and one straight behind the laser (its
  // angle 180 degrees, though its line is the ray's).
  EXPECT_FALSE(vertexUnderLaser(list, kLaser));
  // The same angle (to the last digits: UTM coordinates round): the nearer; the same vertex
  // twice (two measurements that share it), the first.
  list[0].points[1] = offRay(9.0, 0.4);
  list[1].points[0] = offRay(3.0, 0.4);
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{1, 0}));
  list[2].points[0] = list[1].points[0];
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{1, 0}));
  const Measurement shared = list[2];
  list.insert(list.begin(), shared);
  EXPECT_EQ(vertexUnderLaser(list, kLaser), (MeasurementVertex{0, 0}));
  list.erase(list.begin());
  // Any length of direction; a wider cone when asked.
  EXPECT_EQ(vertexUnderLaser(list, {kA, {0.0, 0.25, 0.0}}), (MeasurementVertex{1, 0}));
  EXPECT_EQ(vertexUnderLaser(list, kLaser, 0.01), std::nullopt);
  EXPECT_FALSE(vertexUnderLaser(std::vector<Measurement>{}, kLaser));
}

// A press on a vertex grabs it; the drags move it in the document (and the value follows, the
// distance of the new points); the release ends the grab where the last drag left it.
TEST(HeadsetMeasureTool, AGrabbedVertexFollowsTheDragsUntilTheRelease) {
  HeadsetMeasureTool tool;
  std::vector<Measurement> list{
      {.kind = MeasurementKind::Point, .points = {kC}},
      {.kind = MeasurementKind::Distance, .points = {kB, offRay(6.0, 0.1)}}};
  EXPECT_FALSE(tool.grab(kRightHand, list, {kA, {1.0, 0.0, 0.0}})) << "no vertex along +x";
  EXPECT_FALSE(tool.grabbed(kRightHand));
  const auto grabbed = tool.grab(kRightHand, list, kLaser);
  EXPECT_EQ(grabbed, (MeasurementVertex{1, 1}));
  EXPECT_EQ(tool.grabbed(kRightHand), grabbed);
  EXPECT_FALSE(tool.grabbed(kLeftHand));
  EXPECT_TRUE(tool.inProgress().points.empty()) << "a grab is no pick";
  const glm::dvec3 to{512352.5, 5412347.0, 316.0};
  EXPECT_EQ(tool.drag(kRightHand, list, kC), grabbed);
  EXPECT_EQ(tool.drag(kRightHand, list, to), grabbed);
  EXPECT_EQ(list[1].points, (std::vector<glm::dvec3>{kB, to}));
  EXPECT_EQ(list[0].points, std::vector<glm::dvec3>{kC});
  const double dx = 2.5, dy = 5412347.0 - 5412349.5, dz = 316.0 - 314.25;
  EXPECT_DOUBLE_EQ(measurementValues(list[1]).total, std::sqrt(dx * dx + dy * dy + dz * dz));
  EXPECT_FALSE(tool.drag(kLeftHand, list, kA)) << "the left hand holds nothing";
  EXPECT_EQ(tool.release(kRightHand), grabbed);
  EXPECT_FALSE(tool.grabbed(kRightHand));
  EXPECT_FALSE(tool.drag(kRightHand, list, kA));
  EXPECT_EQ(list[1].points[1], to);
  EXPECT_FALSE(tool.release(kRightHand));
}

// Each hand holds its own vertex; a vertex the other hand holds passes to the hand that presses
// on it; a measurement that leaves the document takes its grab with it, and later ones' grabs
// follow their new index.
TEST(HeadsetMeasureTool, GrabsAreAHandsEachAndFollowTheDocumentsDeletions) {
  HeadsetMeasureTool tool;
  std::vector<Measurement> list{{.kind = MeasurementKind::Point, .points = {offRay(5.0, 0.0)}},
                                {.kind = MeasurementKind::Point, .points = {kC}},
                                {.kind = MeasurementKind::Point, .points = {kB}}};
  EXPECT_EQ(tool.grab(kLeftHand, list, kLaser), (MeasurementVertex{0, 0}));
  EXPECT_EQ(tool.grab(kRightHand, list, kLaser), (MeasurementVertex{0, 0}));
  EXPECT_FALSE(tool.grabbed(kLeftHand)) << "passed to the right hand";
  EXPECT_EQ(tool.grab(kLeftHand, list, {kA, kB - kA}), (MeasurementVertex{2, 0}));
  tool.erased(1);
  EXPECT_EQ(tool.grabbed(kLeftHand), (MeasurementVertex{1, 0}));
  EXPECT_EQ(tool.grabbed(kRightHand), (MeasurementVertex{0, 0}));
  tool.erased(0);
  EXPECT_FALSE(tool.grabbed(kRightHand));
  EXPECT_EQ(tool.grabbed(kLeftHand), (MeasurementVertex{0, 0}));
}

// The measurement under the laser: a vertex's first; else the lines between the vertices within
// the cone, an area's closing line included, the least angle winning.
TEST(HeadsetMeasureTool, TheMeasurementUnderTheLaserIsAVertexsElseTheNearestLinesInAngle) {
  // A distance crossing the ray 8 along it, 0.3 degrees to its side (its ends 1 to either side,
  // so a vertex is far off the ray); an area whose closing line (last to first vertex) crosses
  // the ray 10 along it at 0.2 degrees.
  const double side8 = 8.0 * std::tan(glm::radians(0.3)),
               side10 = 10.0 * std::tan(glm::radians(0.2));
  std::vector<Measurement> list{
      {.kind = MeasurementKind::Distance,
       .points = {kA + glm::dvec3(-1.0, 8.0, side8), kA + glm::dvec3(1.0, 8.0, side8)}},
      {.kind = MeasurementKind::Area,
       .points = {kA + glm::dvec3(-1.0, 10.0, side10), kA + glm::dvec3(0.0, 10.0, 5.0),
                  kA + glm::dvec3(1.0, 10.0, side10)}}};
  EXPECT_FALSE(vertexUnderLaser(list, kLaser));
  EXPECT_EQ(measurementUnderLaser(list, kLaser), 1u) << "0.2 degrees, the area's closing line";
  list[1].kind = MeasurementKind::Distance;  // the same points, not closed: no line near the ray
  EXPECT_EQ(measurementUnderLaser(list, kLaser), 0u) << "0.3 degrees, the distance's line";
  list[0].points[1].z = list[0].points[0].z = 8.0 * std::tan(glm::radians(0.6));
  EXPECT_FALSE(measurementUnderLaser(list, kLaser)) << "0.6 degrees";
  // A vertex wins over a nearer line in angle.
  list.push_back({.kind = MeasurementKind::Point, .points = {offRay(30.0, 0.45)}});
  list[0].points[1].z = list[0].points[0].z = 0.0;
  EXPECT_EQ(measurementUnderLaser(list, kLaser), 2u);
  // A line from behind the laser's origin to in front of it: only the part in front counts.
  const std::vector<Measurement> through{
      {.kind = MeasurementKind::Distance,
       .points = {kA + glm::dvec3(0.0, -5.0, 1.0), kA + glm::dvec3(0.0, 5.0, 1.0)}}};
  EXPECT_FALSE(measurementUnderLaser(through, kLaser)) << "it passes beside the origin, 90 degrees";
  EXPECT_EQ(measurementUnderLaser(through, {kA, {0.0, 4.0, 1.0}}), 0u) << "along its front part";
}

// The trigger's release is an event (the end of a grab), and so is losing the hand's tracking
// with the trigger down.
TEST(HeadsetMeasureTool, TheTriggersReleaseIsAnEvent) {
  Locomotion locomotion(StagePlacement{});
  XrInput input;
  input.hands[kRightHand].tracked = true;
  input.hands[kRightHand].trigger = 1.0f;
  LocomotionEvents events = locomotion.update(input);
  EXPECT_TRUE(events.pick[kRightHand]);
  EXPECT_FALSE(events.let_go[kRightHand]);
  input.hands[kRightHand].trigger = 0.5f;  // between the thresholds: still down
  EXPECT_FALSE(locomotion.update(input).let_go[kRightHand]);
  input.hands[kRightHand].trigger = 0.1f;
  events = locomotion.update(input);
  EXPECT_TRUE(events.let_go[kRightHand]);
  EXPECT_FALSE(events.let_go[kLeftHand]);
  EXPECT_FALSE(locomotion.update(input).let_go[kRightHand]) << "once";
  input.hands[kRightHand].trigger = 1.0f;
  EXPECT_TRUE(locomotion.update(input).pick[kRightHand]);
  input.hands[kRightHand].tracked = false;
  EXPECT_TRUE(locomotion.update(input).let_go[kRightHand]) << "tracking lost";
  EXPECT_FALSE(locomotion.update(input).let_go[kRightHand]);
}

}  // namespace
}  // namespace parallax
