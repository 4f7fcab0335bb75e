// What the controllers did in one frame, as the OpenXR action system reports it (xr_actions.cpp),
// in stage space (metres, y up). Plain data, no OpenXR types, so that locomotion can be tested
// without a runtime.
#pragma once

#include <array>
#include <glm/glm.hpp>

#include "xr/stage_mapping.h"

namespace parallax {

enum XrHandIndex { kLeftHand = 0, kRightHand = 1 };

struct XrHandInput {
  bool tracked = false;        // the grip and aim poses are valid this frame
  StagePose grip;              // where the hand holds the controller (grabbing moves this point)
  StagePose aim;               // the pointing ray: from its position along its -z (the laser)
  float trigger = 0.0f;        // 0..1: picks points, or grabs the vertex under the laser
                               // (select on the simple controller)
  float squeeze = 0.0f;        // 0..1: grabs the world (menu on the simple controller)
  glm::dvec2 thumbstick{0.0};  // -1..1, x right, y forward: fly (left), snap turn (right)
  bool primary = false;        // A (X on a left Touch controller): teleport to the laser's point
  bool secondary = false;      // B (Y on a left Touch controller): the next measurement tool;
                               // held, deletes the measurement under the laser (or the last);
                               // pressed while the trigger holds a vertex, removes that vertex
};

struct XrInput {
  std::array<XrHandInput, 2> hands;  // kLeftHand, kRightHand
  glm::dvec3 head{0.0};              // between the eyes, stage
  double period_s = 1.0 / 90.0;      // the runtime's predicted display period: one frame's time
};

}  // namespace parallax
