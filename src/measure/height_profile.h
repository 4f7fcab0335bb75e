// The height profile along a polyline: the points in a vertical corridor around it, as (distance
// along the line, height) pairs, and their export as CSV or LAS.
//
// The corridor: a point belongs to the profile when its horizontal (XY) distance to some
// segment of the polyline, measured perpendicular to it with the foot inside the segment, is at
// most width / 2. Its station (distance along the line) is the horizontal length of the segments
// before that one plus the foot's distance from the segment's start; where corridors of two
// segments overlap (inside a bend), the nearer segment takes the point, so no point is listed
// twice. Points beyond the polyline's ends are not in it (the corridor has square ends). Heights
// are the points' z. Everything in double, world coordinates.
//
// From an octree, every node whose box meets the corridor's bounding box is read (every point of
// an octree is in exactly one node: the profile is at full detail, not the level drawn).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "core/point_cloud.h"
#include "lod/octree.h"

namespace parallax {

struct ProfileSample {
  double station = 0;      // horizontal distance along the polyline from its first vertex
  double offset = 0;       // signed horizontal distance from the line (left of it positive)
  glm::dvec3 position{0};  // world coordinates; position.z is the height
};

struct HeightProfile {
  std::vector<ProfileSample> samples;  // ordered by station
  // The profiled points with every attribute of their source, in the same order as `samples`
  // (for the LAS export).
  PointCloud points;
};

// The profile of `cloud` along `line` (at least two vertices with distinct XY positions for a
// non-empty result) within `width` (> 0, the corridor's full width).
HeightProfile extractProfile(const PointCloud& cloud, const std::vector<glm::dvec3>& line,
                             double width);
// The same over every node of `octree` that may hold such points; expands the hierarchy where
// needed. At most `max_points` samples (the nearest to the line are not preferred: extraction
// stops with an InputError saying the corridor holds too many points, rather than a partial
// profile that looks complete).
HeightProfile extractProfile(Octree& octree, const std::vector<glm::dvec3>& line, double width,
                             std::uint64_t max_points = 50'000'000);

// The lowest and highest heights (z) of the profile's points; {0, 0} when it has none.
struct HeightRange {
  double low = 0.0;
  double high = 0.0;
};
HeightRange heightRange(const HeightProfile& profile);

// CSV: a header line "station,height,offset,x,y,z", then one line per sample, full precision
// (17 significant digits: the values read back exactly). Written under a temporary name and
// renamed. Throws std::runtime_error naming the file when it cannot be written.
void writeProfileCsv(const HeightProfile& profile, const std::filesystem::path& path);
// LAS: the profiled points with every attribute and the source's quantization (io/las_writer.h).
void writeProfileLas(const HeightProfile& profile, const std::filesystem::path& path);

}  // namespace parallax
