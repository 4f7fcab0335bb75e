#include "xr/headset_measure_tool.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace parallax {

namespace {

// The window's order of the tools (viewer/measure_tool.h), from distance round to point.
MeasurementKind nextHeadsetTool(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Distance:
      return MeasurementKind::Height;
    case MeasurementKind::Height:
      return MeasurementKind::Area;
    case MeasurementKind::Area:
      return MeasurementKind::Angle;
    case MeasurementKind::Angle:
      return MeasurementKind::Profile;
    case MeasurementKind::Profile:
      return MeasurementKind::Point;
    case MeasurementKind::Point:
      break;
  }
  return MeasurementKind::Distance;
}

// A point seen from the laser: its depth along the ray and its offset across it at unit depth,
// whose length is the tangent of its angle from the ray (a plane at depth 1, as a camera's).
struct LaserSight {
  double depth;
  glm::dvec3 across;
};

LaserSight sightOf(const LaserRay& ray, const glm::dvec3& unit, const glm::dvec3& point) {
  const glm::dvec3 v = point - ray.origin;
  const double depth = glm::dot(v, unit);
  return {depth, depth > 0 ? (v - depth * unit) / depth : glm::dvec3(0.0)};
}

glm::dvec3 unitDirection(const LaserRay& ray) {
  assert(glm::length(ray.direction) > 0 && "a laser needs a direction");
  return glm::normalize(ray.direction);
}

// The least tangent of the angle between the ray and a segment's points in front of its origin;
// infinity when none is. A straight segment in front of the origin seen at unit depth is a
// straight segment (a central projection), so the least angle is that segment's least distance
// from the ray's centre. A segment running behind the origin is cut where it is a millionth of
// its length in front (its picture there lies far outside any cone worth asking about).
double segmentTangent(const LaserRay& ray, const glm::dvec3& unit, glm::dvec3 a, glm::dvec3 b) {
  double da = glm::dot(a - ray.origin, unit), db = glm::dot(b - ray.origin, unit);
  if (da < db) {
    std::swap(a, b);
    std::swap(da, db);
  }
  const double least_depth = 1e-6 * glm::length(b - a);
  if (da <= least_depth) return std::numeric_limits<double>::infinity();
  if (db < least_depth) {
    b = a + (b - a) * ((da - least_depth) / (da - db));
  }
  const glm::dvec3 qa = sightOf(ray, unit, a).across, qb = sightOf(ray, unit, b).across;
  const glm::dvec3 ab = qb - qa;
  const double length2 = glm::dot(ab, ab);
  const double t = length2 > 0 ? std::clamp(-glm::dot(qa, ab) / length2, 0.0, 1.0) : 0.0;
  return glm::length(qa + t * ab);
}

}  // namespace

std::optional<MeasurementVertex> vertexUnderLaser(std::span<const Measurement> measurements,
                                                  const LaserRay& ray, double cone_deg) {
  const glm::dvec3 unit = unitDirection(ray);
  const double most = std::tan(glm::radians(cone_deg));
  std::optional<MeasurementVertex> best;
  double best_tangent = 0, best_depth = 0;
  for (std::size_t m = 0; m < measurements.size(); ++m) {
    const std::vector<glm::dvec3>& points = measurements[m].points;
    for (std::size_t v = 0; v < points.size(); ++v) {
      const LaserSight sight = sightOf(ray, unit, points[v]);
      if (!(sight.depth > 0)) continue;
      const double tangent = glm::length(sight.across);
      if (tangent > most) continue;
      // The same angle within a rounding's worth (1e-9 of the tangent, 6e-8 degrees), as two
      // measurements that share a vertex are: the nearer, then the first.
      const bool same = std::abs(tangent - best_tangent) <= 1e-9;
      if (!best || (!same && tangent < best_tangent) || (same && sight.depth < best_depth)) {
        best = MeasurementVertex{m, v};
        best_tangent = tangent;
        best_depth = sight.depth;
      }
    }
  }
  return best;
}

std::optional<std::size_t> measurementUnderLaser(std::span<const Measurement> measurements,
                                                 const LaserRay& ray, double cone_deg) {
  if (const auto vertex = vertexUnderLaser(measurements, ray, cone_deg)) {
    return vertex->measurement;
  }
  const glm::dvec3 unit = unitDirection(ray);
  double best_tangent = std::tan(glm::radians(cone_deg));
  std::optional<std::size_t> best;
  for (std::size_t m = 0; m < measurements.size(); ++m) {
    const Measurement& measurement = measurements[m];
    const std::size_t n = measurement.points.size();
    // An area's lines close the polygon (as the overlay draws it).
    const std::size_t segments =
        measurement.kind == MeasurementKind::Area && n >= 3 ? n : (n >= 2 ? n - 1 : 0);
    for (std::size_t i = 0; i < segments; ++i) {
      const double tangent =
          segmentTangent(ray, unit, measurement.points[i], measurement.points[(i + 1) % n]);
      if (tangent < best_tangent || (!best && tangent == best_tangent)) {
        best = m;
        best_tangent = tangent;
      }
    }
  }
  return best;
}

std::optional<Measurement> HeadsetMeasureTool::pick(const glm::dvec3& point) {
  current_.points.push_back(point);
  // Area is the one kind left open: the tool button closes it.
  if (current_.kind == MeasurementKind::Area ||
      current_.points.size() < minimumVertices(current_.kind)) {
    return std::nullopt;
  }
  Measurement done = current_;
  if (done.kind == MeasurementKind::Profile) done.profile_width = profile_width_;
  current_.points.clear();
  return done;
}

std::optional<Measurement> HeadsetMeasureTool::toolButton() {
  if (current_.kind == MeasurementKind::Area &&
      current_.points.size() >= minimumVertices(MeasurementKind::Area)) {
    Measurement done = current_;
    current_.points.clear();
    return done;
  }
  current_ = Measurement{.kind = nextHeadsetTool(current_.kind)};
  return std::nullopt;
}

std::optional<MeasurementVertex> HeadsetMeasureTool::grab(int hand,
                                                          std::span<const Measurement> measurements,
                                                          const LaserRay& ray) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  const auto vertex = vertexUnderLaser(measurements, ray);
  if (!vertex) return std::nullopt;
  if (grabbed_[1 - hand] == vertex) grabbed_[1 - hand].reset();
  grabbed_[hand] = vertex;
  return vertex;
}

std::optional<MeasurementVertex> HeadsetMeasureTool::grabbed(int hand) const {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  return grabbed_[hand];
}

std::optional<MeasurementVertex> HeadsetMeasureTool::drag(int hand,
                                                          std::vector<Measurement>& measurements,
                                                          const glm::dvec3& point) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  const auto vertex = grabbed_[hand];
  if (!vertex) return std::nullopt;
  assert(vertex->measurement < measurements.size() &&
         vertex->vertex < measurements[vertex->measurement].points.size() &&
         "drag the document the grab was made in (tell erased() what left it)");
  measurements[vertex->measurement].points[vertex->vertex] = point;
  return vertex;
}

std::optional<MeasurementVertex> HeadsetMeasureTool::release(int hand) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  const auto vertex = grabbed_[hand];
  grabbed_[hand].reset();
  return vertex;
}

void HeadsetMeasureTool::erased(std::size_t index) {
  for (std::optional<MeasurementVertex>& vertex : grabbed_) {
    if (!vertex) continue;
    if (vertex->measurement == index) {
      vertex.reset();
    } else if (vertex->measurement > index) {
      --vertex->measurement;
    }
  }
}

}  // namespace parallax
