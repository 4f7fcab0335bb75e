// Moving the world with the controllers (xr/locomotion.h): after each gesture, every file point's
// stage position is where the gesture's rule puts it, computed here from the rule alone.
#include "xr/locomotion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace parallax {
namespace {

const StagePlacement kStart{{512345.25, 5412345.75, 312.5}, 1.0, 0.0};

const std::vector<glm::dvec3> kFilePoints{
    {512345.25, 5412345.75, 312.5}, {512350.0, 5412349.5, 314.25}, {512339.125, 5412355.0, 310.0}};

// Ry(a) v, written out: a turn about the stage's vertical, counter-clockwise seen from above.
glm::dvec3 turnY(const glm::dvec3& v, double a) {
  return {std::cos(a) * v.x + std::sin(a) * v.z, v.y, -std::sin(a) * v.x + std::cos(a) * v.z};
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

XrHandInput hand(const glm::dvec3& grip, float squeeze = 0.0f) {
  XrHandInput h;
  h.tracked = true;
  h.grip.position = grip;
  h.aim.position = grip;
  h.squeeze = squeeze;
  return h;
}

TEST(Locomotion, YawTurnsTheIssuesMappingAboutTheVertical) {
  StagePlacement p = kStart;
  p.yaw = 0.3;
  for (const auto& x : kFilePoints) {
    const glm::dvec3 d = x - p.origin;
    expectNear(fileToStage(p, x), turnY({d.x, d.z, -d.y}, 0.3));
    expectNear(stageToFile(p, fileToStage(p, x)), x);
  }
}

TEST(Locomotion, OneHandGrabMovesTheWorldWithTheHand) {
  Locomotion loco(kStart);
  XrInput input;
  input.hands[kRightHand] = hand({0.2, 1.1, -0.3}, 1.0f);
  loco.update(input);
  const glm::dvec3 moved{0.2 + 0.5, 1.1 - 0.25, -0.3 - 1.0};
  input.hands[kRightHand] = hand(moved, 1.0f);
  // The hand's turn does not tilt the world (fixed horizon).
  input.hands[kRightHand].grip.orientation =
      glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 1, 0)));
  loco.update(input);
  for (const auto& x : kFilePoints) {
    expectNear(fileToStage(loco.placement(), x),
               fileToStage(kStart, x) + glm::dvec3(0.5, -0.25, -1.0));
  }
  EXPECT_EQ(loco.placement().yaw, 0.0);
  EXPECT_EQ(loco.placement().scale, 1.0);
  // Let go: the world stays where it was left.
  const StagePlacement left_at = loco.placement();
  input.hands[kRightHand] = hand({0.0, 0.0, 0.0}, 0.0f);
  loco.update(input);
  EXPECT_EQ(loco.placement().origin, left_at.origin);
}

TEST(Locomotion, TwoHandsScaleAndTurnTheWorldAboutTheirMidpoint) {
  Locomotion loco(kStart);
  XrInput input;
  input.hands[kLeftHand] = hand({-0.2, 1.2, -0.4}, 1.0f);
  input.hands[kRightHand] = hand({0.2, 1.2, -0.4}, 1.0f);
  loco.update(input);
  const glm::dvec3 m0{0.0, 1.2, -0.4};
  const double angle = glm::radians(20.0);
  const glm::dvec3 m = m0 + glm::dvec3(0.1, 0.05, -0.2);
  const glm::dvec3 half = turnY({0.3, 0.0, 0.0}, angle);  // 1.5 times the span, turned 20 deg
  input.hands[kLeftHand] = hand(m - half, 1.0f);
  input.hands[kRightHand] = hand(m + half, 1.0f);
  loco.update(input);
  for (const auto& x : kFilePoints) {
    expectNear(fileToStage(loco.placement(), x),
               turnY(fileToStage(kStart, x) - m0, angle) * 1.5 + m);
  }
  EXPECT_NEAR(loco.placement().scale, 1.5, 1e-12);
  EXPECT_NEAR(loco.placement().yaw, angle, 1e-12);
}

TEST(Locomotion, SnapTurnsOncePerPushAboutTheHead) {
  Locomotion loco(kStart);
  XrInput input;
  input.head = {0.3, 1.6, 0.2};
  input.hands[kRightHand] = hand({0.2, 1.0, -0.2});
  input.hands[kRightHand].thumbstick = {0.9, 0.0};
  loco.update(input);
  loco.update(input);  // still pushed: no second turn
  const double a = glm::radians(30.0);
  for (const auto& x : kFilePoints) {
    expectNear(fileToStage(loco.placement(), x),
               turnY(fileToStage(kStart, x) - input.head, a) + input.head);
  }
  input.hands[kRightHand].thumbstick = {0.0, 0.0};
  loco.update(input);
  input.hands[kRightHand].thumbstick = {-1.0, 0.0};
  loco.update(input);  // back to the start
  for (const auto& x : kFilePoints)
    expectNear(fileToStage(loco.placement(), x), fileToStage(kStart, x));
}

TEST(Locomotion, FlyingMovesAlongTheLeftAimAtTheSetSpeed) {
  Locomotion loco(kStart, {30.0, 2.0});
  XrInput input;
  input.period_s = 0.01;
  input.hands[kLeftHand] = hand({-0.2, 1.0, -0.2});
  // Aiming 90 degrees to the left: forward is stage -x.
  input.hands[kLeftHand].aim.orientation = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 1, 0));
  input.hands[kLeftHand].thumbstick = {0.0, 0.5};
  loco.update(input);
  EXPECT_TRUE(loco.flying());
  for (const auto& x : kFilePoints) {
    // The user moves 0.5 * 2 m/s * 0.01 s towards -x: the world moves +x.
    expectNear(fileToStage(loco.placement(), x), fileToStage(kStart, x) + glm::dvec3(0.01, 0, 0));
  }
  input.hands[kLeftHand].thumbstick = {0.0, 0.05};  // inside the dead zone
  loco.update(input);
  EXPECT_FALSE(loco.flying());
}

TEST(Locomotion, TeleportPutsThePointOnTheFloorUnderTheHead) {
  Locomotion loco(kStart);
  const glm::dvec3 head{0.4, 1.7, -0.1};
  loco.teleportTo(kFilePoints[1], head);
  expectNear(fileToStage(loco.placement(), kFilePoints[1]), {0.4, 0.0, -0.1});
}

TEST(Locomotion, TriggerAndButtonReportEachPressOnce) {
  Locomotion loco(kStart);
  XrInput input;
  input.hands[kRightHand] = hand({0.2, 1.0, -0.2});
  input.hands[kRightHand].trigger = 0.9f;
  EXPECT_TRUE(loco.update(input).pick[kRightHand]);
  EXPECT_FALSE(loco.update(input).pick[kRightHand]);
  input.hands[kRightHand].trigger = 0.1f;
  input.hands[kRightHand].primary = true;
  const LocomotionEvents events = loco.update(input);
  EXPECT_FALSE(events.pick[kRightHand]);
  EXPECT_TRUE(events.teleport[kRightHand]);
  EXPECT_FALSE(events.teleport[kLeftHand]);
}

}  // namespace
}  // namespace parallax
