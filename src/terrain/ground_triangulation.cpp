// GroundTriangulation (ground_triangulation.h) over CGAL's 2D Delaunay triangulation.
#include "terrain/ground_triangulation.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <tuple>
#include <utility>
#include <vector>

namespace parallax {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<double, Kernel>;  // info: z
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, DataStructure>;
using Point = Kernel::Point_2;

}  // namespace

struct GroundTriangulation::State {
  Delaunay triangulation;
  Delaunay::Face_handle last;  // where the next search starts
};

GroundTriangulation::GroundTriangulation(std::span<const std::array<double, 3>> ground,
                                         bool holds_hull)
    : state_(std::make_unique<State>()), holds_hull_(holds_hull) {
  // Sorted by (x, y, z) and one point per (x, y): the set, not the order the caller found the
  // points in, decides which of equal points stays.
  std::vector<std::array<double, 3>> sorted(ground.begin(), ground.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::pair<Point, double>> points;
  points.reserve(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (i > 0 && sorted[i][0] == sorted[i - 1][0] && sorted[i][1] == sorted[i - 1][1]) continue;
    points.emplace_back(Point(sorted[i][0], sorted[i][1]), sorted[i][2]);
  }
  state_->triangulation.insert(points.begin(), points.end());
}

GroundTriangulation::~GroundTriangulation() = default;

GroundTriangulation::Answer GroundTriangulation::at(double x, double y) const {
  const Delaunay& dt = state_->triangulation;
  Answer answer;
  if (dt.number_of_vertices() == 0) return answer;
  const Point q(x, y);
  if (dt.dimension() == 2) {
    Delaunay::Locate_type type;
    int index = 0;
    Delaunay::Face_handle face = dt.locate(q, type, index, state_->last);
    state_->last = face;
    if (type == Delaunay::FACE || type == Delaunay::EDGE || type == Delaunay::VERTEX) {
      if (dt.is_infinite(face)) face = face->neighbor(face->index(dt.infinite_vertex()));
      const Point& a = face->vertex(0)->point();
      const Point& b = face->vertex(1)->point();
      const Point& c = face->vertex(2)->point();
      // Barycentric weights in double, centred on a (the coordinates may be UTM-sized).
      const double bx = b.x() - a.x(), by = b.y() - a.y(), cx = c.x() - a.x(), cy = c.y() - a.y();
      const double qx = x - a.x(), qy = y - a.y();
      const double det = bx * cy - by * cx;
      const double wb = (qx * cy - qy * cx) / det, wc = (bx * qy - by * qx) / det;
      const double za = face->vertex(0)->info();
      answer.z = za + wb * (face->vertex(1)->info() - za) + wc * (face->vertex(2)->info() - za);
      const Point centre = CGAL::circumcenter(a, b, c);
      const double radius = std::sqrt(CGAL::squared_distance(centre, a));
      answer.reach = std::sqrt(CGAL::squared_distance(centre, q)) + radius;
      answer.centre_x = centre.x(), answer.centre_y = centre.y(), answer.radius = radius;
      return answer;
    }
  }
  const Delaunay::Vertex_handle nearest = dt.nearest_vertex(q);
  answer.z = nearest->info();
  if (holds_hull_) {
    answer.reach = std::sqrt(CGAL::squared_distance(nearest->point(), q));
    answer.centre_x = x, answer.centre_y = y, answer.radius = answer.reach;
  }
  return answer;
}

std::vector<std::array<double, 3>> GroundTriangulation::convexHull(
    std::span<const std::array<double, 3>> points) {
  std::vector<std::pair<Point, double>> in;
  in.reserve(points.size());
  for (const auto& p : points) in.emplace_back(Point(p[0], p[1]), p[2]);
  std::vector<Point> xy;
  xy.reserve(in.size());
  for (const auto& p : in) xy.push_back(p.first);
  std::vector<Point> hull;
  CGAL::convex_hull_2(xy.begin(), xy.end(), std::back_inserter(hull));
  // The z of each hull vertex: the lowest of the points at its x and y.
  std::sort(in.begin(), in.end(), [](const auto& a, const auto& b) {
    return std::make_tuple(a.first.x(), a.first.y(), a.second) <
           std::make_tuple(b.first.x(), b.first.y(), b.second);
  });
  std::vector<std::array<double, 3>> out;
  for (const Point& h : hull) {
    const auto at = std::lower_bound(in.begin(), in.end(), h, [](const auto& a, const Point& b) {
      return std::make_pair(a.first.x(), a.first.y()) < std::make_pair(b.x(), b.y());
    });
    out.push_back({h.x(), h.y(), at->second});
  }
  return out;
}

}  // namespace parallax
