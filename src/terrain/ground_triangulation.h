// The ground's surface as a 2D Delaunay triangulation of ground points (CGAL's
// Delaunay_triangulation_2 with exact predicates, Debian's header-only libcgal-dev): the
// height above ground of `process --height-above-ground`.
//
// Every answer says how far around the query it depends on the points (its reach), so that a
// caller holding only the ground points of a region can tell whether the answer is the one the
// whole ground's triangulation would give: a Delaunay triangle is one of the whole ground's when
// no ground point lies in its circumcircle, which is known once every ground point within the
// circle is held (the points being in general position: four cocircular points have two
// triangulations, and each may come out).
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace parallax {

class GroundTriangulation {
 public:
  // `ground`: x, y, z of the ground points, any order; points of equal x and y count once, with
  // the lowest z. Empty: every answer is NaN. `holds_hull`: `ground` holds every vertex of the
  // whole ground's convex hull (convexHull below), so that a point outside this triangulation's
  // hull is outside the whole ground's, and its answer (the nearest ground point) reaches only as
  // far as that point.
  explicit GroundTriangulation(std::span<const std::array<double, 3>> ground,
                               bool holds_hull = false);
  ~GroundTriangulation();
  GroundTriangulation(const GroundTriangulation&) = delete;
  GroundTriangulation& operator=(const GroundTriangulation&) = delete;

  struct Answer {
    double z = std::numeric_limits<double>::quiet_NaN();  // the ground's height at (x, y)
    // The answer depends on the ground points within this distance of (x, y) only: the
    // farthest point of the triangle's circumcircle; outside the convex hull, where the height
    // is the nearest ground point's, infinite (a larger ground may hold the point) unless the
    // triangulation holds the whole ground's hull (then the nearest point's distance).
    double reach = std::numeric_limits<double>::infinity();
    // The disc the answer depends on, where `reach` is finite: the triangle's circumcircle, or
    // outside the hull the disc around (x, y) through the nearest ground point. Only the ground
    // points inside it could change the answer, so a caller that knows where the ground can be
    // (its bounding box) needs only the part of the disc there (step_height.cpp).
    double centre_x = 0.0, centre_y = 0.0, radius = std::numeric_limits<double>::infinity();
  };
  // Linear within the triangle holding (x, y); outside the convex hull the nearest ground point.
  // The search starts from the last answer's triangle (a walk, O(distance)): ask in a spatial
  // order. Not safe to call from several threads at once.
  Answer at(double x, double y) const;

  // The vertices of the convex hull of `points` (x and y; z kept), counter-clockwise.
  static std::vector<std::array<double, 3>> convexHull(
      std::span<const std::array<double, 3>> points);

 private:
  struct State;
  std::unique_ptr<State> state_;
  bool holds_hull_ = false;
};

}  // namespace parallax
