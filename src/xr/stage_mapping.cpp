#include "xr/stage_mapping.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace parallax {
namespace {

// Stage vectors to file vectors: stage (a, b, c) = (x, z, -y), so x = a, y = -c, z = b. A rotation
// (determinant 1): +90 degrees about x.
const glm::dquat kStageToFile = glm::angleAxis(glm::radians(90.0), glm::dvec3(1, 0, 0));

// Ry(angle) and its inverse written out, so that a yaw of 0 leaves every value exactly as the
// issue's mapping gives it.
glm::dvec3 turnY(const glm::dvec3& v, double angle) {
  if (angle == 0.0) return v;
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

}  // namespace

glm::dvec3 baseCentre(const Bounds3& bounds) {
  if (bounds.empty()) return glm::dvec3(0.0);
  return {(bounds.min[0] + bounds.max[0]) / 2, (bounds.min[1] + bounds.max[1]) / 2, bounds.min[2]};
}

StagePlacement tabletopPlacement(const Bounds3& bounds) {
  StagePlacement placement;
  placement.origin = baseCentre(bounds);
  if (!bounds.empty()) {
    const auto size = bounds.size();
    const double largest = std::max({double(size[0]), double(size[1]), double(size[2])});
    if (largest > 0) placement.scale = 1.0 / largest;
  }
  return placement;
}

glm::dvec3 fileToStage(const StagePlacement& p, const glm::dvec3& file) {
  const glm::dvec3 d = file - p.origin;
  return turnY({d.x * p.scale, d.z * p.scale, -d.y * p.scale}, p.yaw);
}

glm::dvec3 stageToFileVector(const StagePlacement& p, const glm::dvec3& stage) {
  const glm::dvec3 s = turnY(stage, -p.yaw);
  return glm::dvec3(s.x, -s.z, s.y) / p.scale;
}

glm::dvec3 stageToFile(const StagePlacement& p, const glm::dvec3& stage) {
  return p.origin + stageToFileVector(p, stage);
}

glm::dquat stageToFileRotation(const StagePlacement& p) {
  return kStageToFile * glm::angleAxis(-p.yaw, glm::dvec3(0, 1, 0));
}

Camera cameraAtStagePose(const StagePlacement& placement, const StagePose& pose) {
  Camera camera;
  camera.projection = Projection::Perspective;
  camera.world_up = glm::dvec3(0, 0, 1);
  camera.position = stageToFile(placement, pose.position);
  camera.orientation = glm::normalize(stageToFileRotation(placement) * pose.orientation);
  camera.pivot = camera.position + camera.forward();
  return camera;
}

EyeView eyeView(const StagePlacement& placement, const EyeFov& fov, const StagePose& eye, int x,
                int width, int height) {
  assert(fov.left < fov.right && fov.down < fov.up && "eyeView: an empty field of view");
  const double tl = std::tan(fov.left), tr = std::tan(fov.right);
  const double tu = std::tan(fov.up), td = std::tan(fov.down);
  // Pixels per unit of tangent, vertically; the viewport spans +-half_rows / k around the centre.
  const double k = height / (tu - td);
  const int least = int(std::ceil(2.0 * std::max(tu, -td) * k - 1e-9));
  EyeView out;
  int rows = least;
  out.row_error = 1.0;
  // The eye's bottom (tangent td) lies at rows / 2 + td * k: of two heights one puts it within a
  // quarter of a pixel of a whole row.
  for (int candidate = least; candidate <= least + 1; ++candidate) {
    const double bottom = candidate / 2.0 + td * k;
    const int source = std::clamp(int(std::lround(bottom)), 0, candidate - height);
    const double error = std::abs(bottom - source);
    if (error < out.row_error) {
      out.row_error = error;
      out.source_y = source;
      rows = candidate;
    }
  }
  View& view = out.view;
  view.viewport = {x, 0, width, rows};
  view.camera = cameraAtStagePose(placement, eye);
  Camera& camera = view.camera;
  const double half_tan_y = rows / (2.0 * k);
  camera.fov_y_deg = glm::degrees(2.0 * std::atan(half_tan_y));
  // A symmetric frustum of half-tangent (tr - tl) / 2 sheared to its centre (tr + tl) / 2:
  // Camera::projectionMatrix's x += skew * depth gives NDC x = (x / depth + skew) / half.
  camera.off_axis_skew = -(tr + tl) / 2;
  view.projection_aspect = (tr - tl) / (2.0 * half_tan_y);
  return out;
}

}  // namespace parallax
