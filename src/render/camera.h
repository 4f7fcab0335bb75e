// The camera: a position and a quaternion orientation in world (file) coordinates, kept in double
// so that a camera a few metres from a UTM-placed cloud is exact.
//
// Frames: the camera looks down its local -z with +y up and +x right (OpenGL's eye space).
// `orientation` rotates camera-local vectors into world vectors. Angles are radians except
// `fov_y_deg`. Nothing is stored as Euler angles, so no pose has a gimbal lock: orbiting through
// or at the poles only rotates the orientation quaternion.
#pragma once

#include <filesystem>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json_fwd.hpp>
#include <span>

#include "core/bounds.h"

namespace parallax {

enum class Projection { Perspective, Orthographic };
enum class OrbitMode { Turntable, Free };

// Near and far plane distances along the view direction (orthographic near may be negative).
struct ClipRange {
  double near_plane = 0.1;
  double far_plane = 1000.0;
};

struct Camera {
  glm::dvec3 position{0.0, 0.0, 1.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  // camera-to-world rotation (w, x, y, z)
  glm::dvec3 pivot{0.0, 0.0, 0.0};             // centre of orbits and dollies
  glm::dvec3 world_up{0.0, 0.0, 1.0};          // turntable axis and fly up/down
  double fov_y_deg = 60.0;                     // perspective: vertical field of view
  double ortho_height = 2.0;                   // orthographic: world height of the view
  Projection projection = Projection::Perspective;
  // Off-axis stereo (render/stereo.h): the eye's offset along `right` divided by the convergence
  // distance. The projection shears eye space by x += skew * depth, which skews the frustum so
  // that the plane at the convergence distance has zero parallax. 0 for a mono camera (the
  // projection is then exactly the symmetric one). Not saved with the camera: eyes are derived.
  double off_axis_skew = 0.0;

  friend bool operator==(const Camera&, const Camera&) = default;

  glm::dvec3 forward() const { return orientation * glm::dvec3(0, 0, -1); }
  glm::dvec3 right() const { return orientation * glm::dvec3(1, 0, 0); }
  glm::dvec3 up() const { return orientation * glm::dvec3(0, 1, 0); }
  // Distance from the camera to the pivot along the view direction (at least a tiny positive).
  double pivotDepth() const;

  // Looks from `eye` at `target` with `up` as the world's up (the image's up where it is not
  // parallel to the view; another axis is chosen where it is). Sets the pivot to `target`.
  void lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);

  // Rotates the camera around the pivot; a positive pitch raises the view direction, a positive
  // yaw turns it to the left. Turntable: `yaw` around world_up, `pitch` around the
  // camera's right axis, the elevation clamped to the poles (reachable, never flipped over).
  // Free: `yaw` around the camera's up axis and `pitch` around its right axis, no limits.
  void orbit(double yaw, double pitch, OrbitMode mode);

  // Moves camera and pivot parallel to the image so that the point at the pivot's depth follows a
  // drag of (dx, dy) pixels (y down, as window coordinates are) in a viewport `height` pixels high.
  void pan(double dx_px, double dy_px, int viewport_height);

  // Moves towards (factor < 1) or away from (factor > 1) the point at the pivot's depth under the
  // cursor, given in normalised device coordinates (-1..1, y up). That point stays under the
  // cursor.
  void dolly(double factor, const glm::dvec2& cursor_ndc, double aspect);

  // Fly mode: moves by (right, up along world_up, forward) world units; the pivot follows.
  void flyMove(const glm::dvec3& right_up_forward);
  // Fly mode: turns the head (yaw around world_up, pitch around right), position fixed.
  void flyLook(double yaw, double pitch);

  // Keeps the orientation and places the camera as near as it can with the whole box in view
  // (every corner inside the frustum, the box in front of the camera); the pivot becomes the
  // box's centre. Orthographic: sets ortho_height so that the box fits.
  void fitToBounds(const Bounds3& bounds, double aspect);
  // Keeps the orientation and frames the points as they project: the camera moves along the view
  // and sideways (the pivot with it) until the points' projected extent is centred and fills
  // the view on its tighter axis, `margin` of the half-width (or half-height) left free on each
  // side of that axis and at least that much on the other. Every point ends up in front of the
  // camera; the pivot goes to the middle of their depth on the view axis. Sets the position and
  // ortho_height (in perspective, to the view's height at the pivot). Much tighter than
  // fitToBounds for real scans, whose box corners (sky over the ground, empty corners of an
  // irregular site) are nowhere near a point. Empty `points`: nothing changes.
  // [x_from, x_to]: the part of the view's width to frame them in, in normalised device
  // coordinates (-1 the left edge, 1 the right; x_from < x_to), where the rest is covered (the
  // viewer's panel): the projected extent is centred in that part and fills it as it would fill
  // a view of that width, and the pivot is on the ray through its centre.
  static constexpr double kFitMargin = 0.03;
  void fitToPoints(std::span<const glm::dvec3> points, double aspect, double margin = kFitMargin,
                   double x_from = -1.0, double x_to = 1.0);

  // World to eye, in double. Callers subtract chunk origins in double before going to float.
  glm::dmat4 viewMatrix() const;
  // Eye to clip with reversed depth (near maps to 1, far to 0) for a [0, 1] depth range
  // (glClipControl GL_ZERO_TO_ONE) and a float depth buffer: precision where it is needed.
  // With an off_axis_skew, the symmetric projection times the eye-space shear.
  glm::dmat4 projectionMatrix(double aspect, const ClipRange& range) const;
  // Near and far planes that keep every point of `bounds` in front of the camera unclipped.
  ClipRange clipRange(const Bounds3& bounds) const;
};

// A pleasant default: the cloud seen from the south-west, 35 degrees above the horizon, z up.
Camera defaultCameraFor(const Bounds3& bounds, double aspect);

nlohmann::json cameraToJson(const Camera& camera);
// Throws std::runtime_error naming the field that is missing or malformed.
Camera cameraFromJson(const nlohmann::json& json);
void saveCamera(const Camera& camera, const std::filesystem::path& path);
Camera loadCamera(const std::filesystem::path& path);

}  // namespace parallax
