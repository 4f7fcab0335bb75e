#include "xr/locomotion.h"

#include <cassert>
#include <cmath>

namespace parallax {
namespace {

// Hysteresis on the analogue inputs, so that a trigger resting near a threshold does not click.
constexpr float kPressAt = 0.75f, kReleaseAt = 0.25f;
constexpr float kGrabAt = 0.6f, kLetGoAt = 0.4f;
constexpr double kSnapAt = 0.7, kSnapReArmAt = 0.3;
constexpr double kStickDeadZone = 0.1;
// Below this distance between the hands (metres) a two-hand grab only moves: a ratio of two tiny
// lengths is noise.
constexpr double kLeastHandSpan = 0.01;

// The angle of a horizontal stage direction, counter-clockwise seen from above (Ry's sense):
// Ry(a) (1, 0, 0) = (cos a, 0, -sin a).
double headingOf(const glm::dvec3& v) {
  return std::atan2(-v.z, v.x);
}

bool pressed(bool& down, float value, float press, float release) {
  const bool was = down;
  down = was ? value > release : value >= press;
  return down && !was;
}

}  // namespace

StagePlacement translatedBy(const StagePlacement& placement, const glm::dvec3& stage_delta) {
  // s(X) = R M (X - O) S: moving every s by delta moves O by the file vector of -delta.
  StagePlacement out = placement;
  out.origin = placement.origin - stageToFileVector(placement, stage_delta);
  return out;
}

StagePlacement turnedAbout(const StagePlacement& placement, const glm::dvec3& stage_pivot,
                           double angle) {
  StagePlacement turned = placement;
  turned.yaw = placement.yaw + angle;  // s1(X) = Ry(angle) s(X)
  const glm::dvec3 turned_pivot = glm::angleAxis(angle, glm::dvec3(0, 1, 0)) * stage_pivot;
  return translatedBy(turned, stage_pivot - turned_pivot);
}

StagePlacement scaledAbout(const StagePlacement& placement, const glm::dvec3& stage_pivot,
                           double factor) {
  StagePlacement scaled = placement;
  scaled.scale = placement.scale * factor;  // s1(X) = s(X) factor
  return translatedBy(scaled, stage_pivot - stage_pivot * factor);
}

Locomotion::Locomotion(const StagePlacement& start, const LocomotionSettings& settings)
    : settings_(settings), placement_(start), grab_start_(start) {}

LocomotionEvents Locomotion::update(const XrInput& input) {
  LocomotionEvents events;
  std::array<bool, 2> hold{};
  std::array<glm::dvec3, 2> grip{};
  for (int h = 0; h < 2; ++h) {
    const XrHandInput& hand = input.hands[h];
    grip[h] = hand.grip.position;
    hold[h] = hand.tracked && hand.squeeze >= (holding_[h] ? kLetGoAt : kGrabAt);
    if (!hand.tracked) {
      events.let_go[h] = trigger_down_[h];
      trigger_down_[h] = primary_down_[h] = secondary_down_[h] = secondary_spent_[h] = false;
      continue;
    }
    const bool trigger_was_down = trigger_down_[h];
    events.pick[h] = pressed(trigger_down_[h], hand.trigger, kPressAt, kReleaseAt);
    events.let_go[h] = trigger_was_down && !trigger_down_[h];
    events.teleport[h] =
        pressed(primary_down_[h], hand.primary ? 1.0f : 0.0f, kPressAt, kReleaseAt);
    // The tool button: a short press at its release, a long one while still held.
    if (hand.secondary && !secondary_down_[h]) {
      secondary_down_[h] = true;
      secondary_held_s_[h] = 0.0;
      secondary_spent_[h] = false;
      events.tool_down[h] = true;
    } else if (hand.secondary) {
      secondary_held_s_[h] += input.period_s;
      // Within half a period: a runtime's period is whole nanoseconds (11 111 111 at 90 Hz), and
      // 45 of them fall short of 0.5 s.
      if (!secondary_spent_[h] &&
          secondary_held_s_[h] + 0.5 * input.period_s >= kLongPressSeconds) {
        secondary_spent_[h] = true;
        events.remove[h] = true;
      }
    } else if (secondary_down_[h]) {
      secondary_down_[h] = false;
      events.tool[h] = !secondary_spent_[h];
    }
  }
  // A grab restarts from where things are whenever a hand takes hold or lets go, so the world
  // never jumps.
  if (hold != holding_) {
    holding_ = hold;
    grab_start_ = placement_;
    grip_start_ = grip;
  }
  flying_ = false;
  if (hold[0] && hold[1]) {
    const glm::dvec3 m0 = (grip_start_[0] + grip_start_[1]) / 2.0;
    const glm::dvec3 m = (grip[0] + grip[1]) / 2.0;
    const glm::dvec3 d0 = grip_start_[1] - grip_start_[0], d = grip[1] - grip[0];
    const double span0 = glm::length(d0), span = glm::length(d);
    const double factor = span0 >= kLeastHandSpan && span >= kLeastHandSpan ? span / span0 : 1.0;
    const bool level0 = std::hypot(d0.x, d0.z) >= kLeastHandSpan;
    const bool level = std::hypot(d.x, d.z) >= kLeastHandSpan;
    const double angle = level0 && level ? headingOf(d) - headingOf(d0) : 0.0;
    placement_ = translatedBy(scaledAbout(turnedAbout(grab_start_, m0, angle), m0, factor), m - m0);
    return events;
  }
  for (int h = 0; h < 2; ++h) {
    if (hold[h]) {
      placement_ = translatedBy(grab_start_, grip[h] - grip_start_[h]);
      return events;
    }
  }
  const XrHandInput& right = input.hands[kRightHand];
  const double turn = right.tracked ? right.thumbstick.x : 0.0;
  if (snap_armed_ && std::abs(turn) > kSnapAt) {
    const double angle = glm::radians(settings_.snap_turn_deg) * (turn > 0 ? 1.0 : -1.0);
    placement_ = turnedAbout(placement_, input.head, angle);
    snap_armed_ = false;
  } else if (std::abs(turn) < kSnapReArmAt) {
    snap_armed_ = true;
  }
  const XrHandInput& left = input.hands[kLeftHand];
  if (left.tracked && glm::length(left.thumbstick) > kStickDeadZone) {
    const glm::dvec3 forward = left.aim.orientation * glm::dvec3(0, 0, -1);
    const glm::dvec3 right_dir = left.aim.orientation * glm::dvec3(1, 0, 0);
    const glm::dvec3 velocity =
        (right_dir * left.thumbstick.x + forward * left.thumbstick.y) * settings_.fly_speed;
    placement_ = translatedBy(placement_, -velocity * input.period_s);
    flying_ = true;
  }
  return events;
}

void Locomotion::teleportTo(const glm::dvec3& file_point, const glm::dvec3& head) {
  const glm::dvec3 floor(head.x, 0.0, head.z);
  placement_ = translatedBy(placement_, floor - fileToStage(placement_, file_point));
  grab_start_ = placement_;
}

void Locomotion::claimToolPress(int hand) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  if (secondary_down_[hand]) secondary_spent_[hand] = true;
}

}  // namespace parallax
