// The headset's measurement tools (xr/headset_measure_tool.h): which picks make which measurement,
// and what the tool button does. The values themselves are measure/'s (tests/measure).
#include "xr/headset_measure_tool.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace parallax
