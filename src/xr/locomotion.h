// Moving the world with the controllers (issue 24, item 4): grab to move, two-hand scale, snap
// turns, flying and teleporting, as changes of the stage placement (stage_mapping.h). The user
// stays where the runtime tracks them; the world moves around them. Every change is a translation
// in the stage, a uniform scale or a turn about the stage's vertical axis: the horizon is never
// tilted (the comfort rule the thesis raised), whatever the hands do.
//
// The exact rules, which tests check against their own arithmetic (s(X) is a file point's stage
// position before the change, s'(X) after it):
//   grab, one hand (squeeze held):  s'(X) = s(X) + (g - g0), g the grip position now, g0 where
//                                    the grab began (the hand's turn is ignored).
//   two hands (both squeezed):       s'(X) = Ry(a) (s(X) - m0) f + m, m and m0 the midpoints of
//                                    the grips now and when both began, f the ratio of their
//                                    distances, a the turn of the line between them seen from
//                                    above (its horizontal direction's change).
//   snap turn (right stick's x past 0.7, once until it returns below 0.3):
//                                    s'(X) = Ry(a) (s(X) - h) + h, h the head; a = +snap for a
//                                    push right (the world turns left: the user turned right).
//   fly (left stick):                s'(X) = s(X) - (x r + y f) speed dt, r and f the left aim's
//                                    right and forward, dt the display period.
//   teleport (a file point P):       s'(X) = s(X) + (h_floor - s(P)), h_floor = (h.x, 0, h.z):
//                                    the point comes to the floor under the head.
#pragma once

#include <array>

#include "xr/stage_mapping.h"
#include "xr/xr_input.h"

namespace parallax {

// s'(X) = s(X) + delta.
StagePlacement translatedBy(const StagePlacement& placement, const glm::dvec3& stage_delta);
// s'(X) = Ry(angle) (s(X) - pivot) + pivot.
StagePlacement turnedAbout(const StagePlacement& placement, const glm::dvec3& stage_pivot,
                           double angle);
// s'(X) = (s(X) - pivot) factor + pivot; factor > 0.
StagePlacement scaledAbout(const StagePlacement& placement, const glm::dvec3& stage_pivot,
                           double factor);

struct LocomotionSettings {
  double snap_turn_deg = 30.0;
  double fly_speed = 2.0;  // stage metres per second at a full stick, whatever the world's scale
};

// How long the secondary (tool) button is held to delete the last measurement instead: a press
// is held this long on the first frame where the display periods of the frames since it went
// down add up to it within half a period (frames, not measured seconds, as flying counts them:
// 45 frames after the press at 90 Hz).
constexpr double kLongPressSeconds = 0.5;

// What a frame's input asks of the application beyond the placement, per hand: a pick (the
// trigger went down; or a grab of the vertex under the laser, headset_measure_tool.h), the
// trigger let go (ending a grab; also when the hand is no longer tracked), a teleport (the
// primary button went down), the tool button (the secondary button let go before
// kLongPressSeconds: a short press) or a delete (the secondary button held for
// kLongPressSeconds; once, and its release is then nothing). `tool_down` is the secondary
// button going down, for the one use that acts at once (removing a held vertex): a caller that
// acts on it calls Locomotion::claimToolPress, and that press then makes no tool or delete event.
struct LocomotionEvents {
  std::array<bool, 2> pick{false, false};
  std::array<bool, 2> let_go{false, false};
  std::array<bool, 2> teleport{false, false};
  std::array<bool, 2> tool{false, false};
  std::array<bool, 2> remove{false, false};
  std::array<bool, 2> tool_down{false, false};
};

class Locomotion {
 public:
  explicit Locomotion(const StagePlacement& start, const LocomotionSettings& settings = {});

  // Applies one frame's input to the placement; returns the frame's button presses.
  LocomotionEvents update(const XrInput& input);
  // Puts the file point at the floor under the head (a teleport; see above).
  void teleportTo(const glm::dvec3& file_point, const glm::dvec3& head);
  // The secondary button's press that is down on `hand` has acted (its tool_down was used): its
  // release is no tool event and holding it deletes nothing. Nothing when the button is up.
  void claimToolPress(int hand);

  const StagePlacement& placement() const { return placement_; }
  // True while the left stick flies (the vignette narrows the view then).
  bool flying() const { return flying_; }

 private:
  LocomotionSettings settings_;
  StagePlacement placement_;
  // The grab that is under way: which hands hold, and the placement and grips when it began.
  std::array<bool, 2> holding_{false, false};
  StagePlacement grab_start_;
  std::array<glm::dvec3, 2> grip_start_{};
  bool snap_armed_ = true;
  bool flying_ = false;
  std::array<bool, 2> trigger_down_{false, false};
  std::array<bool, 2> primary_down_{false, false};
  std::array<bool, 2> secondary_down_{false, false};
  std::array<double, 2> secondary_held_s_{0.0, 0.0};  // display periods since it went down
  // This press has acted (deleted, or was claimed): no more events until the next one.
  std::array<bool, 2> secondary_spent_{false, false};
};

}  // namespace parallax
