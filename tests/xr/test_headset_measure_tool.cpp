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

// --- adding and removing a vertex of a finished distance or area ------------------------------

// The tool button's press is an event of its own (tool_down, the frame it goes down); a press
// claimed by the caller (it removed a held vertex) makes no tool event at its release and deletes
// nothing however long it is held; the next press is an ordinary one again.
TEST(HeadsetMeasureTool, AClaimedSecondaryPressIsNoToolEventAndDeletesNothing) {
  Locomotion locomotion(StagePlacement{});
  XrInput input;
  input.period_s = 0.125;
  input.hands[kRightHand].tracked = true;
  locomotion.claimToolPress(kRightHand);  // the button is up: nothing to claim
  input.hands[kRightHand].secondary = true;
  LocomotionEvents events = locomotion.update(input);
  EXPECT_TRUE(events.tool_down[kRightHand]);
  EXPECT_FALSE(events.tool_down[kLeftHand]);
  locomotion.claimToolPress(kRightHand);
  for (int frame = 0; frame < 8; ++frame) {  // a second: twice a long press
    events = locomotion.update(input);
    EXPECT_FALSE(events.tool_down[kRightHand]) << "once a press: " << frame;
    EXPECT_FALSE(events.remove[kRightHand]) << frame;
  }
  input.hands[kRightHand].secondary = false;
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]) << "the claimed press's release";
  // A short press claimed is no tool event either; an unclaimed one is.
  input.hands[kRightHand].secondary = true;
  EXPECT_TRUE(locomotion.update(input).tool_down[kRightHand]);
  locomotion.claimToolPress(kRightHand);
  input.hands[kRightHand].secondary = false;
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = true;
  EXPECT_TRUE(locomotion.update(input).tool_down[kRightHand]);
  input.hands[kRightHand].secondary = false;
  EXPECT_TRUE(locomotion.update(input).tool[kRightHand]);
}

// The line under the laser that takes a vertex: a distance's or an area's (an area's closing one
// too), not a height's, angle's or profile's, whatever their angle; the point on it nearest the
// ray. The points are written so that the nearest point is known: each line runs across the
// ray (file +y from kA) at a known depth, so its nearest point is where it passes x = 0.
TEST(HeadsetMeasureTool, TheSegmentUnderTheLaserIsADistancesOrAnAreasAndItsPointNearestTheRay) {
  const double z8 = 8.0 * std::tan(glm::radians(0.3)), z10 = 10.0 * std::tan(glm::radians(0.2));
  std::vector<Measurement> list{
      // A height and a profile straight across the ray, on it: no vertices to add there.
      {.kind = MeasurementKind::Height,
       .points = {kA + glm::dvec3(-1.0, 5.0, 0.0), kA + glm::dvec3(1.0, 5.0, 0.0)}},
      {.kind = MeasurementKind::Profile,
       .points = {kA + glm::dvec3(-1.0, 6.0, 0.0), kA + glm::dvec3(1.0, 6.0, 0.0)}},
      // A distance of three points whose second line runs slantwise through depth 8 at x = 0,
      // 0.3 degrees above the ray: from x -1 at depth 6 to x 1 at depth 10.
      {.kind = MeasurementKind::Distance,
       .points = {kA + glm::dvec3(-3.0, 2.0, 4.0), kA + glm::dvec3(-1.0, 6.0, z8),
                  kA + glm::dvec3(1.0, 10.0, z8)}},
      // An area whose closing line (vertex 3 to vertex 0) crosses at depth 10, 0.2 degrees above.
      {.kind = MeasurementKind::Area,
       .points = {kA + glm::dvec3(-1.0, 10.0, z10), kA + glm::dvec3(-1.0, 10.0, 5.0),
                  kA + glm::dvec3(1.0, 10.0, 5.0), kA + glm::dvec3(1.0, 10.0, z10)}}};
  EXPECT_EQ(measurementUnderLaser(list, kLaser), 0u) << "the height's line is on the ray";
  auto segment = segmentUnderLaser(list, kLaser);
  ASSERT_TRUE(segment);
  EXPECT_EQ(segment->measurement, 3u) << "0.2 degrees, the area's closing line";
  EXPECT_EQ(segment->segment, 3u);
  const glm::dvec3 on_area = kA + glm::dvec3(0.0, 10.0, z10);
  EXPECT_NEAR(glm::length(segment->closest - on_area), 0.0, 1e-9);
  list[3].points[0].z = list[3].points[3].z = 10.0 * std::tan(glm::radians(0.6));
  segment = segmentUnderLaser(list, kLaser);
  ASSERT_TRUE(segment);
  EXPECT_EQ(segment->measurement, 2u) << "0.3 degrees, the distance's second line";
  EXPECT_EQ(segment->segment, 1u);
  const glm::dvec3 on_distance = kA + glm::dvec3(0.0, 8.0, z8);
  EXPECT_NEAR(glm::length(segment->closest - on_distance), 0.0, 1e-9);
  // A line that ends short of the ray (x from 0.01 to 2 at depth 8): its nearest point is its end.
  list[2].points = {kA + glm::dvec3(0.01, 8.0, 0.0), kA + glm::dvec3(2.0, 8.0, 0.0)};
  segment = segmentUnderLaser(list, kLaser);
  ASSERT_TRUE(segment);
  EXPECT_EQ(segment->measurement, 2u);
  EXPECT_EQ(segment->segment, 0u);
  EXPECT_EQ(segment->closest, list[2].points[0]);
  // Nothing free within the cone: 0.6 degrees and beyond.
  list[2].points[0].x = list[2].points[1].x = 8.0 * std::tan(glm::radians(0.6));
  EXPECT_FALSE(segmentUnderLaser(list, kLaser));
  EXPECT_EQ(measurementUnderLaser(list, kLaser), 0u);
}

// An inserted vertex goes between its line's two ends, the hand holds it (a drag moves it, the
// area's value follows), the other hand's grab of a later vertex follows its new index, and the
// release ends it; a vertex on an area's closing line comes last.
TEST(HeadsetMeasureTool, AnInsertedVertexGoesBetweenItsLinesEndsAndIsHeld) {
  HeadsetMeasureTool tool;
  const glm::dvec3 p0 = kA, p1 = kA + glm::dvec3(4.0, 0.0, 0.0),
                   p2 = kA + glm::dvec3(0.0, 3.0, 0.0);
  std::vector<Measurement> list{{.kind = MeasurementKind::Area, .points = {p0, p1, p2}}};
  // The left hand holds vertex 2 (p2).
  ASSERT_EQ(tool.grab(kLeftHand, list, {kA + glm::dvec3(0.0, 3.0, 10.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{0, 2}));
  const glm::dvec3 mid = kA + glm::dvec3(2.0, -1.0, 0.0);  // under p0 -> p1, pulled out 1 m
  const MeasurementVertex added =
      tool.insert(kRightHand, list, {.measurement = 0, .segment = 0, .closest = mid}, mid);
  EXPECT_EQ(added, (MeasurementVertex{0, 1}));
  EXPECT_EQ(list[0].points, (std::vector<glm::dvec3>{p0, mid, p1, p2}));
  EXPECT_EQ(tool.grabbed(kRightHand), added);
  EXPECT_TRUE(tool.holdsInserted(kRightHand));
  EXPECT_EQ(tool.grabbed(kLeftHand), (MeasurementVertex{0, 3})) << "p2 is vertex 3 now";
  EXPECT_FALSE(tool.holdsInserted(kLeftHand));
  EXPECT_TRUE(tool.inProgress().points.empty()) << "an insert is no pick";
  // The triangle (4 x 3 / 2 = 6 m²) and the triangle p0, mid, p1 below it (4 x 1 / 2 = 2 m²).
  EXPECT_DOUBLE_EQ(measurementValues(list[0]).area_3d, 8.0);
  const glm::dvec3 to = kA + glm::dvec3(2.0, -2.0, 0.0);
  EXPECT_EQ(tool.drag(kRightHand, list, to), added);
  EXPECT_EQ(list[0].points[1], to);
  EXPECT_DOUBLE_EQ(measurementValues(list[0]).area_3d, 10.0);
  EXPECT_EQ(tool.release(kRightHand), added);
  EXPECT_FALSE(tool.holdsInserted(kRightHand));
  EXPECT_EQ(tool.release(kLeftHand), (MeasurementVertex{0, 3}));
  // The closing line (p2 -> p0), segment 3: the new vertex is the last.
  const glm::dvec3 left = kA + glm::dvec3(-1.0, 1.5, 0.0);
  EXPECT_EQ(tool.insert(kLeftHand, list, {.measurement = 0, .segment = 3, .closest = left}, left),
            (MeasurementVertex{0, 4}));
  EXPECT_EQ(list[0].points, (std::vector<glm::dvec3>{p0, to, p1, p2, left}));
  // Taken over by the other hand, it is still an added vertex.
  EXPECT_EQ(tool.grab(kRightHand, list, {left + glm::dvec3(0.0, 0.0, 5.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{0, 4}));
  EXPECT_FALSE(tool.grabbed(kLeftHand));
  EXPECT_TRUE(tool.holdsInserted(kRightHand));
  tool.erased(0);
  EXPECT_FALSE(tool.holdsInserted(kRightHand));
}

// The tool button on a held vertex removes it while its measurement keeps its kind's minimum
// (an area 3 points, a distance 2); at the minimum it stays, still held; a height's never goes.
TEST(HeadsetMeasureTool, TheToolButtonRemovesAHeldVertexDownToItsKindsMinimum) {
  HeadsetMeasureTool tool;
  std::vector<Measurement> list{
      {.kind = MeasurementKind::Height, .points = {kA, kB}},
      {.kind = MeasurementKind::Area, .points = {kA, kB, kC, kA + glm::dvec3(1.0, 0.0, 0.0)}},
      {.kind = MeasurementKind::Distance, .points = {kA, kB, kC}}};
  EXPECT_FALSE(tool.removeHeld(kRightHand, list)) << "nothing held";
  // The area's vertex 2 (kC), the other hand holding its vertex 3.
  ASSERT_EQ(tool.grab(kLeftHand, list, {kA + glm::dvec3(1.0, 0.0, 50.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{1, 3}));
  ASSERT_EQ(tool.grab(kRightHand, list, {kC + glm::dvec3(0.0, 0.0, 50.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{1, 2}));
  auto removal = tool.removeHeld(kRightHand, list);
  ASSERT_TRUE(removal);
  EXPECT_TRUE(removal->removed);
  EXPECT_EQ(removal->vertex, (MeasurementVertex{1, 2}));
  EXPECT_EQ(list[1].points, (std::vector<glm::dvec3>{kA, kB, kA + glm::dvec3(1.0, 0.0, 0.0)}));
  EXPECT_FALSE(tool.grabbed(kRightHand)) << "the vertex is gone, and its grab";
  EXPECT_EQ(tool.grabbed(kLeftHand), (MeasurementVertex{1, 2})) << "the later vertex's new index";
  // Three left: the area keeps them all.
  removal = tool.removeHeld(kLeftHand, list);
  ASSERT_TRUE(removal);
  EXPECT_FALSE(removal->removed);
  EXPECT_EQ(removal->vertex, (MeasurementVertex{1, 2}));
  EXPECT_EQ(list[1].points.size(), 3u);
  EXPECT_EQ(tool.grabbed(kLeftHand), (MeasurementVertex{1, 2})) << "still held";
  tool.release(kLeftHand);
  // The distance: three points to two, then no further.
  ASSERT_EQ(tool.grab(kRightHand, list, {kC + glm::dvec3(0.0, 0.0, 50.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{2, 2}));
  removal = tool.removeHeld(kRightHand, list);
  ASSERT_TRUE(removal && removal->removed);
  EXPECT_EQ(list[2].points, (std::vector<glm::dvec3>{kA, kB}));
  ASSERT_EQ(tool.grab(kRightHand, list, {kB + glm::dvec3(0.0, 0.0, 50.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{0, 1}))
      << "the height's, the first of the three that share kB";
  removal = tool.removeHeld(kRightHand, list);
  ASSERT_TRUE(removal);
  EXPECT_FALSE(removal->removed) << "a height has exactly two";
  EXPECT_EQ(list[0].points, (std::vector<glm::dvec3>{kA, kB}));
  tool.release(kRightHand);
  // A profile of three points (the window draws polylines) keeps them all: the headset's profile
  // is a straight section, and its vertices are only moved.
  list.push_back({.kind = MeasurementKind::Profile, .points = {kA, kB, kC}});
  ASSERT_EQ(tool.grab(kRightHand, list, {kC + glm::dvec3(0.0, 0.0, 50.0), {0.0, 0.0, -1.0}}),
            (MeasurementVertex{3, 2}));
  removal = tool.removeHeld(kRightHand, list);
  ASSERT_TRUE(removal);
  EXPECT_FALSE(removal->removed) << "no vertex of a profile goes";
  EXPECT_EQ(list[3].points, (std::vector<glm::dvec3>{kA, kB, kC}));
}

}  // namespace
}  // namespace parallax
