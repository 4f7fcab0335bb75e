#include "xr/headset_measure_tool.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

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

// The line of `measurements` nearest the ray in angle within `cone_deg`, of those whose kind
// `admits`: its measurement and its first vertex (the first in the list on a tie).
struct NearestLine {
  std::size_t measurement;
  std::size_t segment;
};
template <typename Admits>
std::optional<NearestLine> nearestLine(std::span<const Measurement> measurements,
                                       const LaserRay& ray, double cone_deg, Admits admits) {
  const glm::dvec3 unit = unitDirection(ray);
  double best_tangent = std::tan(glm::radians(cone_deg));
  std::optional<NearestLine> best;
  for (std::size_t m = 0; m < measurements.size(); ++m) {
    const Measurement& measurement = measurements[m];
    if (!admits(measurement.kind)) continue;
    const std::size_t n = measurement.points.size();
    // An area's lines close the polygon (as the overlay draws it).
    const std::size_t segments =
        measurement.kind == MeasurementKind::Area && n >= 3 ? n : (n >= 2 ? n - 1 : 0);
    for (std::size_t i = 0; i < segments; ++i) {
      const double tangent =
          segmentTangent(ray, unit, measurement.points[i], measurement.points[(i + 1) % n]);
      if (tangent < best_tangent || (!best && tangent == best_tangent)) {
        best = NearestLine{m, i};
        best_tangent = tangent;
      }
    }
  }
  return best;
}

// The point of the segment a..b nearest the half-line origin + t unit (t >= 0) in 3D: the
// common perpendicular's foot on the segment when it falls inside both, else clamped to the
// segment, and to the origin (t = 0) when the ray's nearest point would lie behind it.
glm::dvec3 closestOnSegmentToRay(const glm::dvec3& origin, const glm::dvec3& unit,
                                 const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 e = b - a, w = a - origin;
  const double ee = glm::dot(e, e), eu = glm::dot(e, unit);
  const double ew = glm::dot(e, w), uw = glm::dot(unit, w);
  if (!(ee > 0)) return a;
  // d/ds and d/dt of |w + s e - t unit|^2 at zero: t = uw + s eu, s (ee - eu^2) = uw eu - ew.
  const double denominator = ee - eu * eu;  // ee |sin|^2 of the angle between line and ray
  double s = denominator > 1e-12 * ee ? std::clamp((uw * eu - ew) / denominator, 0.0, 1.0) : 0.0;
  if (uw + s * eu < 0) s = std::clamp(-ew / ee, 0.0, 1.0);  // nearest to the origin itself
  return a + s * e;
}

}  // namespace

bool vertexCountIsFree(MeasurementKind kind) {
  return kind == MeasurementKind::Distance || kind == MeasurementKind::Area;
}

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
  const auto line = nearestLine(measurements, ray, cone_deg, [](MeasurementKind) { return true; });
  if (!line) return std::nullopt;
  return line->measurement;
}

std::optional<MeasurementSegment> segmentUnderLaser(std::span<const Measurement> measurements,
                                                    const LaserRay& ray, double cone_deg) {
  const auto line = nearestLine(measurements, ray, cone_deg, vertexCountIsFree);
  if (!line) return std::nullopt;
  const std::vector<glm::dvec3>& points = measurements[line->measurement].points;
  const glm::dvec3 closest =
      closestOnSegmentToRay(ray.origin, unitDirection(ray), points[line->segment],
                            points[(line->segment + 1) % points.size()]);
  return MeasurementSegment{line->measurement, line->segment, closest};
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
  inserted_[hand] = false;
  if (grabbed_[1 - hand] == vertex) {
    // Taken over: a vertex the other hand added is still one added.
    grabbed_[1 - hand].reset();
    inserted_[hand] = std::exchange(inserted_[1 - hand], false);
  }
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
  inserted_[hand] = false;
  return vertex;
}

void HeadsetMeasureTool::erased(std::size_t index) {
  for (int h = 0; h < 2; ++h) {
    std::optional<MeasurementVertex>& vertex = grabbed_[h];
    if (!vertex) continue;
    if (vertex->measurement == index) {
      vertex.reset();
      inserted_[h] = false;
    } else if (vertex->measurement > index) {
      --vertex->measurement;
    }
  }
}

MeasurementVertex HeadsetMeasureTool::insert(int hand, std::vector<Measurement>& measurements,
                                             const MeasurementSegment& segment,
                                             const glm::dvec3& point) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  assert(segment.measurement < measurements.size() &&
         vertexCountIsFree(measurements[segment.measurement].kind) &&
         segment.segment < measurements[segment.measurement].points.size() &&
         "insert on a segment segmentUnderLaser found in this document");
  std::vector<glm::dvec3>& points = measurements[segment.measurement].points;
  const MeasurementVertex added{segment.measurement, segment.segment + 1};
  points.insert(points.begin() + std::ptrdiff_t(added.vertex), point);
  std::optional<MeasurementVertex>& other = grabbed_[1 - hand];
  if (other && other->measurement == added.measurement && other->vertex >= added.vertex) {
    ++other->vertex;
  }
  grabbed_[hand] = added;
  inserted_[hand] = true;
  return added;
}

bool HeadsetMeasureTool::holdsInserted(int hand) const {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  return grabbed_[hand] && inserted_[hand];
}

std::optional<VertexRemoval> HeadsetMeasureTool::removeHeld(
    int hand, std::vector<Measurement>& measurements) {
  assert((hand == 0 || hand == 1) && "a hand is 0 (left) or 1 (right)");
  const auto vertex = grabbed_[hand];
  if (!vertex) return std::nullopt;
  assert(vertex->measurement < measurements.size() &&
         vertex->vertex < measurements[vertex->measurement].points.size() &&
         "remove from the document the grab was made in (tell erased() what left it)");
  Measurement& measurement = measurements[vertex->measurement];
  if (!vertexCountIsFree(measurement.kind) ||
      measurement.points.size() <= minimumVertices(measurement.kind)) {
    return VertexRemoval{*vertex, false};
  }
  measurement.points.erase(measurement.points.begin() + std::ptrdiff_t(vertex->vertex));
  grabbed_[hand].reset();
  inserted_[hand] = false;
  std::optional<MeasurementVertex>& other = grabbed_[1 - hand];
  if (other && other->measurement == vertex->measurement && other->vertex > vertex->vertex) {
    --other->vertex;
  }
  return VertexRemoval{*vertex, true};
}

}  // namespace parallax
