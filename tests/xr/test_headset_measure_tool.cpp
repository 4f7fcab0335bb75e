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

TEST(HeadsetMeasureTool, TheButtonCyclesDistanceHeightAreaAndDropsWhatIsInProgress) {
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
  // An area of two points cannot be closed: the button moves on to the distance tool.
  EXPECT_FALSE(tool.pick(kA));
  EXPECT_FALSE(tool.pick(kB));
  EXPECT_FALSE(tool.toolButton());
  EXPECT_EQ(tool.kind(), MeasurementKind::Distance);
  EXPECT_TRUE(tool.inProgress().points.empty());
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

// The secondary button (B, or Y) is a press: one tool event until it is let go.
TEST(HeadsetMeasureTool, TheSecondaryButtonIsOneEventAPress) {
  Locomotion locomotion(StagePlacement{});
  XrInput input;
  input.hands[kRightHand].tracked = true;
  input.hands[kRightHand].secondary = true;
  EXPECT_TRUE(locomotion.update(input).tool[kRightHand]);
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = false;
  EXPECT_FALSE(locomotion.update(input).tool[kRightHand]);
  input.hands[kRightHand].secondary = true;
  const LocomotionEvents again = locomotion.update(input);
  EXPECT_TRUE(again.tool[kRightHand]);
  EXPECT_FALSE(again.tool[kLeftHand]);
  EXPECT_FALSE(again.pick[kRightHand]);
}

}  // namespace
}  // namespace parallax
