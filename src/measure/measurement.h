// Measurements and annotations on a point cloud, and their arithmetic in double.
//
// Every position is in the cloud's world (file) coordinates, in double: a measurement at UTM
// eastings of 500 000 m keeps its millimetres (a float there is good to 6 cm). Lengths and
// areas are in the cloud's units (metres for a projected CRS), angles in degrees. The ground
// plane is XY and heights are Z, as in LAS and every projected CRS.
//
// Definitions (what a Potree or CloudCompare user expects, stated so tests can hold them):
//   distance  a polyline: each segment's 3D length and their sum. Also the horizontal (XY) length
//             of each and the total, and the height difference of each segment.
//   height    two points: dz = z1 - z0 (signed), and the horizontal and 3D distances.
//   area      a closed polygon of the vertices in order (the last joined to the first):
//             3D area = |Newell vector| / 2 = |sum over edges of p_i x p_(i+1)| / 2. For a planar
//             polygon that is exactly its area, in any orientation; for a non-planar one it is the
//             area of its projection on the best-fit plane that Newell's normal defines, never
//             more than any surface spanning it. Computed relative to the first vertex, so
//             UTM-sized coordinates do not cancel digits.
//             projected area = |shoelace sum over the XY coordinates| / 2: the map's area.
//             The perimeter is the closed polyline's 3D length.
//   angle     three points: the angle at the middle vertex between the rays to the other two,
//             atan2(|a x b|, a . b) (well conditioned at 0 and 180 degrees, unlike acos).
//   profile   a polyline and a corridor width: the points whose horizontal distance to the
//             polyline is at most width / 2 (measure/height_profile.h).
//   point     one point: its coordinates.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "render/camera.h"

namespace parallax {

enum class MeasurementKind { Point, Distance, Height, Area, Angle, Profile };

// "point", "distance", "height", "area", "angle", "profile" (the JSON names).
std::string_view measurementKindName(MeasurementKind kind);
// The kind named so; std::nullopt for any other text.
std::optional<MeasurementKind> measurementKindFromName(std::string_view name);
// How many vertices a finished measurement of this kind has: exactly (point 1, height 2,
// angle 3), or at least (distance 2, area 3, profile 2).
std::size_t minimumVertices(MeasurementKind kind);
// True for the kinds with an exact vertex count (point, height, angle): they finish themselves.
bool hasFixedVertexCount(MeasurementKind kind);

struct Measurement {
  MeasurementKind kind = MeasurementKind::Distance;
  std::string name;                // shown in the panel and in PNGs; may be empty
  std::vector<glm::dvec3> points;  // world coordinates, in the order clicked
  double profile_width = 1.0;      // profile only: the corridor's full width, world units, > 0
  friend bool operator==(const Measurement&, const Measurement&) = default;
};

// A labelled 3D point, optionally with the camera it is best seen from.
struct Annotation {
  std::string label;
  glm::dvec3 position{0.0};
  std::optional<Camera> camera;
  friend bool operator==(const Annotation&, const Annotation&) = default;
};

// 3D length of each segment of the open polyline (points.size() - 1 values; none for fewer than
// two points).
std::vector<double> segmentLengths(const std::vector<glm::dvec3>& points);
// Their sum.
double polylineLength(const std::vector<glm::dvec3>& points);
// Horizontal (XY) length of the open polyline.
double horizontalLength(const std::vector<glm::dvec3>& points);
// 3D area of the closed polygon (Newell vector, see above); 0 for fewer than three points.
double polygonArea3d(const std::vector<glm::dvec3>& points);
// Area of the closed polygon projected on the XY plane (shoelace); 0 for fewer than three points.
double polygonAreaProjected(const std::vector<glm::dvec3>& points);
// Length of the closed polygon's boundary (the last point joined to the first).
double polygonPerimeter(const std::vector<glm::dvec3>& points);
// The angle at `vertex` between the rays to `a` and `b`, in degrees (0..180); 0 where either ray
// has zero length.
double angleDegrees(const glm::dvec3& a, const glm::dvec3& vertex, const glm::dvec3& b);

// The values a measurement shows, for the panel, the stderr line and the labels in pictures.
// Lengths and heights in world units, areas in square units, the angle in degrees.
struct MeasurementValues {
  std::vector<double> segments;  // distance, profile: each segment (3D); area: each edge
  double total = 0;              // distance, profile: the polyline's 3D length; area: perimeter
  double horizontal = 0;         // distance, height, profile: horizontal length
  double dz = 0;                 // height: z1 - z0; distance: last z - first z
  double area_3d = 0, area_projected = 0;  // area
  double angle_deg = 0;                    // angle
};
// Values of what the measurement holds so far (a growing one too: fewer points give zeros).
MeasurementValues measurementValues(const Measurement& measurement);

// One line, as the viewer prints a finished measurement ("distance 12.345 m (2 points)",
// "area 3D 10.000 m², projected 8.660 m² (4 points)", ...), lengths with `decimals` digits.
std::string describeMeasurement(const Measurement& measurement, int decimals = 3);

// Where each label of the measurement goes and what it says (for the overlay's text):
// a segment's length at its midpoint, the total / area / angle at a vertex.
struct MeasurementLabel {
  glm::dvec3 anchor{0.0};
  std::string text;
};
std::vector<MeasurementLabel> measurementLabels(const Measurement& measurement, int decimals = 2);

}  // namespace parallax
