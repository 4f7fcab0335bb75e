#include "measure/measurement.h"

#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>

namespace parallax {

namespace {

constexpr std::array<std::pair<MeasurementKind, std::string_view>, 6> kKindNames{{
    {MeasurementKind::Point, "point"},
    {MeasurementKind::Distance, "distance"},
    {MeasurementKind::Height, "height"},
    {MeasurementKind::Area, "area"},
    {MeasurementKind::Angle, "angle"},
    {MeasurementKind::Profile, "profile"},
}};

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

double horizontal(const glm::dvec3& a, const glm::dvec3& b) {
  return std::hypot(b.x - a.x, b.y - a.y);
}

}  // namespace

std::string_view measurementKindName(MeasurementKind kind) {
  for (const auto& [k, name] : kKindNames) {
    if (k == kind) return name;
  }
  assert(false && "a MeasurementKind without a name");
  return "distance";
}

std::optional<MeasurementKind> measurementKindFromName(std::string_view name) {
  for (const auto& [k, n] : kKindNames) {
    if (n == name) return k;
  }
  return std::nullopt;
}

std::size_t minimumVertices(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Point:
      return 1;
    case MeasurementKind::Distance:
    case MeasurementKind::Height:
    case MeasurementKind::Profile:
      return 2;
    case MeasurementKind::Area:
    case MeasurementKind::Angle:
      return 3;
  }
  return 2;
}

bool hasFixedVertexCount(MeasurementKind kind) {
  return kind == MeasurementKind::Point || kind == MeasurementKind::Height ||
         kind == MeasurementKind::Angle;
}

std::vector<double> segmentLengths(const std::vector<glm::dvec3>& points) {
  std::vector<double> lengths;
  for (std::size_t i = 1; i < points.size(); ++i) {
    lengths.push_back(glm::length(points[i] - points[i - 1]));
  }
  return lengths;
}

double polylineLength(const std::vector<glm::dvec3>& points) {
  double total = 0;
  for (double length : segmentLengths(points)) total += length;
  return total;
}

double horizontalLength(const std::vector<glm::dvec3>& points) {
  double total = 0;
  for (std::size_t i = 1; i < points.size(); ++i) total += horizontal(points[i - 1], points[i]);
  return total;
}

double polygonArea3d(const std::vector<glm::dvec3>& points) {
  if (points.size() < 3) return 0;
  // Newell's vector, relative to the first vertex: p_i x p_(i+1) of UTM-sized vectors would be
  // differences of products near 1e12, losing the millimetres the coordinates hold.
  glm::dvec3 newell{0.0};
  const glm::dvec3 origin = points[0];
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    newell += glm::cross(points[i] - origin, points[i + 1] - origin);
  }
  return 0.5 * glm::length(newell);
}

double polygonAreaProjected(const std::vector<glm::dvec3>& points) {
  if (points.size() < 3) return 0;
  // The shoelace formula relative to the first vertex (same reason as above); the fan from it
  // gives the same signed sum.
  double twice = 0;
  const glm::dvec3 origin = points[0];
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    const glm::dvec3 a = points[i] - origin, b = points[i + 1] - origin;
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

double polygonPerimeter(const std::vector<glm::dvec3>& points) {
  if (points.size() < 2) return 0;
  return polylineLength(points) + glm::length(points.front() - points.back());
}

double angleDegrees(const glm::dvec3& a, const glm::dvec3& vertex, const glm::dvec3& b) {
  const glm::dvec3 u = a - vertex, v = b - vertex;
  if (glm::length(u) == 0 || glm::length(v) == 0) return 0;
  return glm::degrees(std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)));
}

MeasurementValues measurementValues(const Measurement& m) {
  MeasurementValues values;
  const auto& p = m.points;
  switch (m.kind) {
    case MeasurementKind::Point:
      break;
    case MeasurementKind::Distance:
    case MeasurementKind::Profile:
      values.segments = segmentLengths(p);
      values.total = polylineLength(p);
      values.horizontal = horizontalLength(p);
      if (p.size() >= 2) values.dz = p.back().z - p.front().z;
      break;
    case MeasurementKind::Height:
      if (p.size() >= 2) {
        values.dz = p[1].z - p[0].z;
        values.horizontal = horizontal(p[0], p[1]);
        values.total = glm::length(p[1] - p[0]);
        values.segments = {values.total};
      }
      break;
    case MeasurementKind::Area:
      values.segments = segmentLengths(p);
      if (p.size() >= 3) values.segments.push_back(glm::length(p.front() - p.back()));
      values.total = polygonPerimeter(p);
      values.area_3d = polygonArea3d(p);
      values.area_projected = polygonAreaProjected(p);
      break;
    case MeasurementKind::Angle:
      values.segments = segmentLengths(p);
      if (p.size() >= 3) values.angle_deg = angleDegrees(p[0], p[1], p[2]);
      break;
  }
  return values;
}

std::string describeMeasurement(const Measurement& m, int decimals) {
  const MeasurementValues v = measurementValues(m);
  const std::string count =
      " (" + std::to_string(m.points.size()) + (m.points.size() == 1 ? " point)" : " points)");
  switch (m.kind) {
    case MeasurementKind::Point:
      if (m.points.empty()) return "point (none)";
      return "point " + fixed(m.points[0].x, decimals) + " " + fixed(m.points[0].y, decimals) +
             " " + fixed(m.points[0].z, decimals);
    case MeasurementKind::Distance:
      return "distance " + fixed(v.total, decimals) + " m" + count;
    case MeasurementKind::Height:
      return "height difference " + fixed(v.dz, decimals) + " m, horizontal " +
             fixed(v.horizontal, decimals) + " m, distance " + fixed(v.total, decimals) + " m" +
             count;
    case MeasurementKind::Area:
      return "area 3D " + fixed(v.area_3d, decimals) + " m², projected " +
             fixed(v.area_projected, decimals) + " m², perimeter " + fixed(v.total, decimals) +
             " m" + count;
    case MeasurementKind::Angle:
      return "angle " + fixed(v.angle_deg, decimals) + " degrees" + count;
    case MeasurementKind::Profile:
      return "profile " + fixed(v.total, decimals) + " m long, " +
             fixed(m.profile_width, decimals) + " m wide" + count;
  }
  return {};
}

std::vector<MeasurementLabel> measurementLabels(const Measurement& m, int decimals) {
  std::vector<MeasurementLabel> labels;
  const auto& p = m.points;
  if (p.empty()) return labels;
  const MeasurementValues v = measurementValues(m);
  auto segment_labels = [&](bool closed) {
    const std::size_t n = closed && p.size() >= 3 ? p.size() : p.size() - 1;
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3& a = p[i];
      const glm::dvec3& b = p[(i + 1) % p.size()];
      labels.push_back({0.5 * (a + b), fixed(glm::length(b - a), decimals) + " m"});
    }
  };
  switch (m.kind) {
    case MeasurementKind::Point:
      labels.push_back({p[0], fixed(p[0].x, decimals) + ", " + fixed(p[0].y, decimals) + ", " +
                                  fixed(p[0].z, decimals)});
      break;
    case MeasurementKind::Distance:
      segment_labels(false);
      if (p.size() > 2) labels.push_back({p.back(), "total " + fixed(v.total, decimals) + " m"});
      break;
    case MeasurementKind::Height:
      if (p.size() >= 2) {
        labels.push_back({0.5 * (p[0] + p[1]), "dz " + fixed(v.dz, decimals) + " m"});
      }
      break;
    case MeasurementKind::Area:
      segment_labels(true);
      if (p.size() >= 3) {
        glm::dvec3 centre{0.0};
        for (const glm::dvec3& q : p) centre += q;
        centre /= double(p.size());
        labels.push_back({centre, fixed(v.area_3d, decimals) + " m² (" +
                                      fixed(v.area_projected, decimals) + " m² on the ground)"});
      }
      break;
    case MeasurementKind::Angle:
      if (p.size() >= 3) labels.push_back({p[1], fixed(v.angle_deg, 1) + "°"});
      break;
    case MeasurementKind::Profile:
      if (p.size() >= 2) {
        labels.push_back({p.back(), "profile " + fixed(v.total, decimals) + " m"});
      }
      break;
  }
  if (!m.name.empty() && !labels.empty()) labels.back().text = m.name + ": " + labels.back().text;
  return labels;
}

}  // namespace parallax
