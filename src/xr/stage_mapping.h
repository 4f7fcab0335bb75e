// Where the cloud stands in the headset's stage, and the eye cameras that follow from it.
//
// File coordinates are z-up (LAS, PLY scans); OpenXR's stage is y-up, metres, -z forward. A file
// point X maps to stage = ((X - Ox) * S, (Z - Oz) * S, -(Y - Oy) * S), with O the file coordinate
// put at the stage origin and S stage metres per file unit (issue 24, item 3): exactly this, so
// that a test can project points itself. Controllers may turn the world about the stage's
// vertical axis (snap turns, a two-hand grab): stage = Ry(yaw) * the above, never a pitch or a
// roll, so the horizon stays level. The mapping is a rotation plus a uniform scale, so angles
// (fields of view) are unchanged and an eye in the stage is a camera in file coordinates with the
// same frustum.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/bounds.h"
#include "render/camera.h"
#include "render/view.h"

namespace parallax {

struct StagePlacement {
  glm::dvec3 origin{0.0};  // file coordinates put at the stage origin
  double scale = 1.0;      // stage metres per file unit, > 0
  // Radians about the stage's +y (counter-clockwise seen from above), applied after the issue's
  // mapping; 0 until a controller turns the world.
  double yaw = 0.0;
};

// The default origin: the centre of the cloud's base (x, y centre, lowest z), so the ground of a
// scan is the stage's floor.
glm::dvec3 baseCentre(const Bounds3& bounds);
// The tabletop preset: the cloud's largest extent becomes 1 m, its base centre the origin.
StagePlacement tabletopPlacement(const Bounds3& bounds);

glm::dvec3 fileToStage(const StagePlacement& placement, const glm::dvec3& file);
glm::dvec3 stageToFile(const StagePlacement& placement, const glm::dvec3& stage);
// A stage direction (an eye's or a controller's orientation) as a file direction.
glm::dquat stageToFileRotation(const StagePlacement& placement);
// A stage vector as a file vector (rotated and divided by the scale; exact axis swaps at yaw 0).
glm::dvec3 stageToFileVector(const StagePlacement& placement, const glm::dvec3& stage);

// An eye as OpenXR reports it: XrFovf's four angles (radians; left and down usually negative)
// and its pose in stage space (XrPosef; orientation turns eye-local vectors into stage ones).
struct EyeFov {
  double left = -0.8, right = 0.8, up = 0.8, down = -0.8;
};
struct StagePose {
  glm::dvec3 position{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  // w, x, y, z
};

// A perspective camera at a stage pose (an eye's, a controller's aim), looking along the pose's
// -z in file coordinates, z up; its field of view is the caller's.
Camera cameraAtStagePose(const StagePlacement& placement, const StagePose& pose);

// The eye as a view of the renderer. Its frusta are symmetric vertically (render's Camera has a
// horizontal off-axis skew, for desktop stereo, and no vertical one), so the eye is drawn into a
// taller viewport `view.viewport` (x, 0, width, canvas rows) whose vertical centre is the eye's
// forward direction, and rows [source_y, source_y + height) of it are the eye's picture of
// width x height pixels: at the same pixels per tangent unit as the eye's own, the tangent
// tan(down) at row source_y within `row_error` (at most 0.25) of a pixel. The horizontal
// asymmetry is the camera's off-axis skew, exact. OpenXR eye space is OpenGL's (-z forward, +y
// up), as the camera's is. `fov` must have left < right and down < up, each in (-pi/2, pi/2).
struct EyeView {
  View view;
  int source_y = 0;
  double row_error = 0.0;
};
EyeView eyeView(const StagePlacement& placement, const EyeFov& fov, const StagePose& eye, int x,
                int width, int height);

}  // namespace parallax
