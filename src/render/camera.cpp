#include "render/camera.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "core/error.h"

namespace parallax {

namespace {

glm::dvec3 anyPerpendicular(const glm::dvec3& v) {
  const glm::dvec3 axis = std::abs(v.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(v, axis));
}

double halfExtent(const Bounds3& bounds) {
  const auto size = bounds.size();
  const double radius = 0.5 * std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
  // A single point still needs a view of some size: a millimetre, or more where the coordinates
  // are so large that a double cannot resolve a millimetre.
  const double magnitude =
      std::max({std::abs(bounds.min[0]), std::abs(bounds.min[1]), std::abs(bounds.min[2])});
  return std::max({radius, 1e-3, magnitude * 1e-12});
}

}  // namespace

double Camera::pivotDepth() const {
  return std::max(glm::dot(pivot - position, forward()), 1e-9);
}

void Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up_hint) {
  glm::dvec3 view = target - eye;
  if (glm::length(view) == 0.0) view = glm::dvec3(0, 1, 0);
  const glm::dvec3 f = glm::normalize(view);
  glm::dvec3 up_axis = glm::length(up_hint) > 0 ? glm::normalize(up_hint) : glm::dvec3(0, 0, 1);
  glm::dvec3 r = glm::cross(f, up_axis);
  // Looking along the up axis: any right vector will do, the turntable still works from there.
  r = glm::length(r) < 1e-12 ? anyPerpendicular(f) : glm::normalize(r);
  const glm::dvec3 u = glm::cross(r, f);
  orientation = glm::normalize(glm::quat_cast(glm::dmat3(r, u, -f)));
  position = eye;
  pivot = glm::length(target - eye) > 0 ? target : eye + f;
  world_up = up_axis;
}

void Camera::orbit(double yaw, double pitch, OrbitMode mode) {
  glm::dquat rotation;
  if (mode == OrbitMode::Turntable) {
    // Clamp the elevation so that the camera reaches the poles but never rolls over them.
    const double elevation = std::asin(std::clamp(glm::dot(forward(), world_up), -1.0, 1.0));
    const double target =
        std::clamp(elevation + pitch, -std::numbers::pi / 2, std::numbers::pi / 2);
    pitch = target - elevation;
    const glm::dquat yaw_rotation = glm::angleAxis(yaw, world_up);
    const glm::dvec3 right_after_yaw = yaw_rotation * right();
    rotation = glm::angleAxis(pitch, right_after_yaw) * yaw_rotation;
  } else {
    rotation = glm::angleAxis(yaw, up()) * glm::angleAxis(pitch, right());
  }
  position = pivot + rotation * (position - pivot);
  orientation = glm::normalize(rotation * orientation);
}

void Camera::pan(double dx_px, double dy_px, int viewport_height) {
  const double view_height = projection == Projection::Perspective
                                 ? 2.0 * pivotDepth() * std::tan(glm::radians(fov_y_deg) / 2)
                                 : ortho_height;
  const double per_pixel = view_height / std::max(viewport_height, 1);
  const glm::dvec3 delta = -right() * (dx_px * per_pixel) + up() * (dy_px * per_pixel);
  position += delta;
  pivot += delta;
}

void Camera::dolly(double factor, const glm::dvec2& cursor_ndc, double aspect) {
  factor = std::max(factor, 1e-6);
  if (projection == Projection::Orthographic) {
    const glm::dvec3 offset = right() * (cursor_ndc.x * ortho_height * 0.5 * aspect) +
                              up() * (cursor_ndc.y * ortho_height * 0.5);
    ortho_height *= factor;
    position += offset * (1.0 - factor);
    pivot += offset * (1.0 - factor);
    return;
  }
  const double tan_half = std::tan(glm::radians(fov_y_deg) / 2);
  const glm::dvec3 ray =
      forward() + right() * (cursor_ndc.x * tan_half * aspect) + up() * (cursor_ndc.y * tan_half);
  const glm::dvec3 target = position + ray * pivotDepth();  // on the pivot's depth plane
  position = target + (position - target) * factor;
}

void Camera::flyMove(const glm::dvec3& right_up_forward) {
  const glm::dvec3 delta =
      right() * right_up_forward.x + world_up * right_up_forward.y + forward() * right_up_forward.z;
  position += delta;
  pivot += delta;
}

void Camera::flyLook(double yaw, double pitch) {
  const double depth = pivotDepth();
  pivot = position;  // turning the head is an orbit around the eye
  orbit(yaw, pitch, OrbitMode::Turntable);
  pivot = position + forward() * depth;
}

void Camera::fitToBounds(const Bounds3& bounds, double aspect) {
  if (bounds.empty()) return;
  const auto c = bounds.center();
  const glm::dvec3 center(c[0], c[1], c[2]);
  const double radius = halfExtent(bounds);
  const glm::dvec3 f = forward(), r = right(), u = up();
  // A margin of a thousandth of the view, so that the extreme points do not sit on the border.
  const double tan_y = std::tan(glm::radians(fov_y_deg) / 2) * 0.999, tan_x = tan_y * aspect;
  // The nearest distance from the centre, along the view, at which all eight corners of the box
  // are inside the frustum: tighter than the bounding sphere, which wastes most of the picture
  // for a flat scan seen from above.
  double distance = 0.0, half_height = 0.0, depth_extent = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p = glm::dvec3(corner & 1 ? bounds.max[0] : bounds.min[0],
                                    corner & 2 ? bounds.max[1] : bounds.min[1],
                                    corner & 4 ? bounds.max[2] : bounds.min[2]) -
                         center;
    const double x = std::abs(glm::dot(p, r)), y = std::abs(glm::dot(p, u)), z = glm::dot(p, f);
    distance = std::max({distance, x / tan_x - z, y / tan_y - z});
    half_height = std::max({half_height, y, x / aspect});
    depth_extent = std::max(depth_extent, -z);
  }
  // A point box (radius only) still gets a view of some size, and the camera stays outside.
  if (distance <= 0.0) distance = radius / tan_y;
  distance = std::max(distance, depth_extent + radius * 1e-3);
  position = center - f * distance;
  pivot = center;
  ortho_height = std::max(2.002 * half_height, 2.0 * radius * 1e-3);
}

void Camera::fitToPoints(std::span<const glm::dvec3> points, double aspect, double margin,
                         double x_from, double x_to) {
  if (points.empty()) return;
  assert(x_from < x_to && "fitToPoints: an empty window");
  // A window [x_from, x_to] of the view: the frame is that of a view `part` as wide, whose centre
  // is `cx` (in tangents of the view's half-angle, perspective) off the axis. Fitting to it is
  // the symmetric fit of the points sheared by x - cx z (the window's centre ray becomes the
  // axis), the camera then moved back by cx d along `right` (see below).
  const double part = 0.5 * (x_to - x_from), window_centre = 0.5 * (x_from + x_to);
  aspect *= part;
  const glm::dvec3 f = forward(), r = right(), u = up();
  // Coordinates relative to the first point (large UTM values cancel before the products).
  const glm::dvec3 origin = points.front();
  // Point i at (x, y, z) along (right, up, forward) from `origin`; the camera at
  // origin + sx right + sy up - d forward sees it at depth z + d and, in perspective, inside the
  // view with `margin` iff |x - sx| <= kx (z + d), kx = tan(fov_x / 2) (1 - margin). That holds
  // for all points iff sx lies in [A - kx d, B + kx d], A = max(x - kx z), B = min(x + kx z),
  // so the nearest d is (A - B) / (2 kx) with sx = (A + B) / 2; the same for y; d the larger.
  const double keep = 1.0 - std::clamp(margin, 0.0, 0.9);
  const double ky = std::tan(glm::radians(fov_y_deg) / 2) * keep, kx = ky * aspect;
  const double cx = projection == Projection::Perspective
                        ? window_centre * std::tan(glm::radians(fov_y_deg) / 2) * aspect / part
                        : 0.0;
  double ax = -INFINITY, bx = INFINITY, ay = -INFINITY, by = INFINITY;
  double min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY, max_y = -INFINITY;
  double min_z = INFINITY, max_z = -INFINITY;
  for (const glm::dvec3& point : points) {
    const glm::dvec3 p = point - origin;
    const double z = glm::dot(p, f), x = glm::dot(p, r) - cx * z, y = glm::dot(p, u);
    ax = std::max(ax, x - kx * z);
    bx = std::min(bx, x + kx * z);
    ay = std::max(ay, y - ky * z);
    by = std::min(by, y + ky * z);
    min_x = std::min(min_x, x), max_x = std::max(max_x, x);
    min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    min_z = std::min(min_z, z), max_z = std::max(max_z, z);
  }
  const double extent = std::max({max_x - min_x, max_y - min_y, max_z - min_z});
  // A single point (or all points in one) still gets a view of some size: a millimetre, or more
  // where the coordinates are too large for a double to resolve one.
  const double magnitude = std::max({std::abs(origin.x), std::abs(origin.y), std::abs(origin.z)});
  const double size = std::max({extent, 1e-3, magnitude * 1e-12});
  double shift_x, shift_y, distance;
  if (projection == Projection::Perspective) {
    shift_x = 0.5 * (ax + bx), shift_y = 0.5 * (ay + by);
    distance = std::max((ax - bx) / (2 * kx), (ay - by) / (2 * ky));
    if (extent <= 0.0) distance = size / ky;
    // Nothing behind or on the eye: the nearest point at least a thousandth of the size ahead.
    distance = std::max(distance, -min_z + size * 1e-3);
    // On the axis with room to spare the band's middle is not the picture's: centre the
    // projected extent (its largest and smallest x / depth as far from 0), by bisection on the
    // shift, which both bounds decrease with.
    auto centre = [&](int axis, double low, double high) {
      for (int step = 0; step < 60 && high - low > 1e-12 * size; ++step) {
        const double shift = 0.5 * (low + high);
        double most = -INFINITY, least = INFINITY;
        for (const glm::dvec3& point : points) {
          const glm::dvec3 p = point - origin;
          const double depth = glm::dot(p, f);
          const double across = axis == 0 ? glm::dot(p, r) - cx * depth : glm::dot(p, u);
          const double ndc = (across - shift) / (depth + distance);
          most = std::max(most, ndc), least = std::min(least, ndc);
        }
        (most + least > 0 ? low : high) = shift;
      }
      return 0.5 * (low + high);
    };
    shift_x = centre(0, ax - kx * distance, bx + kx * distance);
    shift_y = centre(1, ay - ky * distance, by + ky * distance);
  } else {
    shift_x = 0.5 * (min_x + max_x), shift_y = 0.5 * (min_y + max_y);
    const double half_height = std::max(0.5 * (max_y - min_y), 0.5 * (max_x - min_x) / aspect);
    ortho_height = std::max(2.0 * half_height / keep, size * 1e-3);
    // Outside the points, as a perspective camera would be (the view does not depend on it).
    distance = -min_z + size;
  }
  // Where the sheared fit put the camera, in the points' own space: the window's centre ray
  // (tangent cx) passes where the axis passed. Orthographic: the window's centre is
  // window_centre half-widths of the view to the right of the axis.
  const double mid_z = 0.5 * (min_z + max_z);
  const double window_offset = projection == Projection::Perspective
                                   ? 0.0
                                   : window_centre * 0.5 * ortho_height * aspect / part;
  shift_x -= cx * distance + window_offset;
  // The pivot: on the window's centre ray at the depth of the points' middle, so orbits keep
  // them centred in the window.
  pivot =
      origin + r * (shift_x + cx * (mid_z + distance) + window_offset) + u * shift_y + f * mid_z;
  position = origin + r * shift_x + u * shift_y - f * distance;
  if (projection == Projection::Perspective) {
    // What the view spans at the pivot, for a switch to orthographic.
    ortho_height =
        std::max(2.0 * pivotDepth() * std::tan(glm::radians(fov_y_deg) / 2), size * 1e-3);
  }
}

glm::dmat4 Camera::viewMatrix() const {
  const glm::dmat3 world_to_eye = glm::transpose(glm::mat3_cast(orientation));
  glm::dmat4 view(world_to_eye);
  view[3] = glm::dvec4(world_to_eye * -position, 1.0);
  return view;
}

glm::dmat4 Camera::projectionMatrix(double aspect, const ClipRange& range) const {
  // Passing far as near (and the reverse) to the [0, 1] projections reverses the depth.
  glm::dmat4 symmetric;
  if (projection == Projection::Perspective) {
    symmetric =
        glm::perspectiveRH_ZO(glm::radians(fov_y_deg), aspect, range.far_plane, range.near_plane);
  } else {
    const double half_h = ortho_height / 2, half_w = half_h * aspect;
    symmetric =
        glm::orthoRH_ZO(-half_w, half_w, -half_h, half_h, range.far_plane, range.near_plane);
  }
  if (off_axis_skew == 0.0) return symmetric;
  // x += skew * depth, depth = -z in eye space. For a perspective eye at offset e this is the
  // asymmetric frustum of the off-axis method (it shifts NDC x by skew / tan_x for every depth,
  // centring the convergence plane's window on the mono camera's); for an orthographic eye it is
  // the shear that gives parallax linear in depth, zero at the convergence distance.
  glm::dmat4 shear(1.0);
  shear[2][0] = -off_axis_skew;
  return symmetric * shear;
}

ClipRange Camera::clipRange(const Bounds3& bounds) const {
  if (bounds.empty()) return {};
  const glm::dvec3 f = forward();
  double nearest = INFINITY, farthest = -INFINITY;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p(bounds.min[0] + (corner & 1 ? bounds.size()[0] : 0),
                       bounds.min[1] + (corner & 2 ? bounds.size()[1] : 0),
                       bounds.min[2] + (corner & 4 ? bounds.size()[2] : 0));
    const double depth = glm::dot(p - position, f);
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  // A margin for the float rounding of chunk-relative positions on the GPU.
  const double margin = 1e-3 * (farthest - nearest) + 1e-6 * (std::abs(farthest) + 1e-3);
  ClipRange range;
  range.far_plane = farthest + margin;
  if (projection == Projection::Orthographic) {
    range.near_plane = nearest - margin;
  } else {
    // With a reversed float depth buffer a tiny near plane costs no precision: only points closer
    // than a millionth of the far plane (in the eye) are lost.
    range.near_plane = std::max(nearest - margin, range.far_plane * 1e-6);
  }
  if (range.far_plane <= range.near_plane) range.far_plane = range.near_plane * 2 + 1e-6;
  return range;
}

Camera defaultCameraFor(const Bounds3& bounds, double aspect) {
  Camera camera;
  const double azimuth = glm::radians(-120.0), elevation = glm::radians(35.0);
  const glm::dvec3 from(std::cos(elevation) * std::cos(azimuth),
                        std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  camera.lookAt(from, glm::dvec3(0.0), glm::dvec3(0, 0, 1));
  camera.fitToBounds(bounds, aspect);
  return camera;
}

nlohmann::json cameraToJson(const Camera& camera) {
  auto vec = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  const glm::dquat& q = camera.orientation;
  return {
      {"position", vec(camera.position)},
      {"orientation_wxyz", nlohmann::json::array({q.w, q.x, q.y, q.z})},
      {"pivot", vec(camera.pivot)},
      {"world_up", vec(camera.world_up)},
      {"projection", camera.projection == Projection::Perspective ? "perspective" : "orthographic"},
      {"fov_y_deg", camera.fov_y_deg},
      {"ortho_height", camera.ortho_height}};
}

namespace {

std::vector<double> numbers(const nlohmann::json& json, const char* key, std::size_t count) {
  if (!json.contains(key)) throw std::runtime_error(std::string("camera: missing '") + key + "'");
  const auto& value = json.at(key);
  if (!value.is_array() || value.size() != count) {
    throw std::runtime_error(std::string("camera: '") + key + "' must be an array of " +
                             std::to_string(count) + " numbers, found " + value.dump());
  }
  std::vector<double> result;
  for (const auto& item : value) {
    if (!item.is_number()) {
      throw std::runtime_error(std::string("camera: '") + key + "' holds " + item.dump());
    }
    result.push_back(item.get<double>());
  }
  return result;
}

}  // namespace

Camera cameraFromJson(const nlohmann::json& json) {
  if (!json.is_object()) throw std::runtime_error("camera: expected a JSON object");
  Camera camera;
  auto p = numbers(json, "position", 3), q = numbers(json, "orientation_wxyz", 4);
  auto pivot = numbers(json, "pivot", 3);
  camera.position = {p[0], p[1], p[2]};
  camera.orientation = glm::normalize(glm::dquat(q[0], q[1], q[2], q[3]));
  camera.pivot = {pivot[0], pivot[1], pivot[2]};
  if (json.contains("world_up")) {
    auto up = numbers(json, "world_up", 3);
    camera.world_up = {up[0], up[1], up[2]};
  }
  if (json.contains("projection")) {
    const std::string name = json.at("projection").get<std::string>();
    if (name == "perspective") {
      camera.projection = Projection::Perspective;
    } else if (name == "orthographic") {
      camera.projection = Projection::Orthographic;
    } else {
      throw std::runtime_error("camera: 'projection' must be perspective or orthographic, found '" +
                               name + "'");
    }
  }
  if (json.contains("fov_y_deg")) camera.fov_y_deg = json.at("fov_y_deg").get<double>();
  if (json.contains("ortho_height")) camera.ortho_height = json.at("ortho_height").get<double>();
  if (!(camera.fov_y_deg > 0 && camera.fov_y_deg < 180)) {
    throw std::runtime_error("camera: 'fov_y_deg' must be between 0 and 180");
  }
  return camera;
}

void saveCamera(const Camera& camera, const std::filesystem::path& path) {
  std::ofstream out(path);
  out << cameraToJson(camera).dump(2) << "\n";
  if (!out) throw std::runtime_error("cannot write camera file " + path.string());
}

Camera loadCamera(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw InputError({.file = path.string(), .expected = "a camera JSON file", .found = "no file"});
  }
  try {
    return cameraFromJson(nlohmann::json::parse(in));
  } catch (const std::exception& e) {
    throw InputError({.file = path.string(),
                      .expected = "a camera as `parallax view` saves it",
                      .found = e.what()});
  }
}

}  // namespace parallax
