// --height-above-ground: each kept point's z less the ground's height under it, the ground being
// the 2D Delaunay triangulation of the ground points (terrain/ground_triangulation.h), out of
// core: a tile is answered from the ground points of its slab and a halo in x, and the points
// whose triangle's circumcircle reaches past the halo (the triangle could then differ from the
// whole ground's) are answered again with the halo doubled, until none is left, as the
// neighbourhood steps do (NOTES.md), the halo grown at once to the widest reach pending. Memory:
// a tile and the ground points of its halo; a point outside the loaded ground's convex hull
// needs the whole ground (terrain/NOTES.md).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "core/bounds.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"
#include "terrain/ground_triangulation.h"

namespace parallax {

namespace {

constexpr std::uint8_t kGroundClass = 2;

std::vector<std::uint8_t> groundFlags(const TileSet& tiles, std::size_t t) {
  std::vector<std::uint8_t> flags = currentClasses(tiles, t);
  const std::vector<std::uint8_t> kept = tiles.readKept(t);
  for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = kept[i] && flags[i] == kGroundClass;
  return flags;
}

// The x range of the part of the disc (cx, cy, r) inside the ground's bounding box (x0..x1,
// y0..y1): no ground point lies outside the box, so only the ground points with x in that range
// can fall inside the disc. Why it matters: the triangles along the hull's edges in x (the
// cloud's bottom and top rows of ground points, nearly collinear) have circumcircles far wider
// than the cloud, centred outside it; their x extent is the whole cloud's width, but the part of
// them within the box is a sliver along the edge. Measured against the circle's own extent, one
// such triangle near a slab grew its halo to the whole ground. Empty (first > second) where the
// disc misses the box.
std::pair<double, double> xRangeWithin(double cx, double cy, double r, const Bounds3& ground) {
  double half = r;
  if (cy < ground.min[1] || cy > ground.max[1]) {
    const double dy = cy < ground.min[1] ? ground.min[1] - cy : cy - ground.max[1];
    if (!(dy < r)) return {1.0, 0.0};
    half = std::sqrt((r - dy) * (r + dy));
  }
  return {std::max(cx - half, ground.min[0]), std::min(cx + half, ground.max[0])};
}

}  // namespace

void runHeightAboveGroundStep(const HeightAboveGroundStep&, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  if (!tiles.has(0, "class_in")) writeInputClasses(context);
  // The whole ground's convex hull (the hull of each tile's hull), added to every tile's ground:
  // a point outside a tile's triangulation is then outside the whole ground's, and answered by
  // its nearest ground point without loading the whole ground.
  std::uint64_t ground_points = 0;
  std::vector<std::array<double, 3>> hull;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> flags = groundFlags(tiles, t);
    std::vector<std::array<double, 3>> ground;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (flags[i]) ground.push_back({points[i].x, points[i].y, points[i].z});
    }
    ground_points += ground.size();
    const std::vector<std::array<double, 3>> own = GroundTriangulation::convexHull(ground);
    hull.insert(hull.end(), own.begin(), own.end());
  }
  hull = GroundTriangulation::convexHull(hull);
  Bounds3 ground_box;  // the ground's bounding box: its hull's
  for (const auto& v : hull) ground_box.extend(v[0], v[1], v[2]);
  if (ground_points == 0 && tiles.points() > 0) {
    throw std::invalid_argument(context.label +
                                ": no ground point (class 2) in the input; classify it first "
                                "(--ground smrf before --height-above-ground)");
  }
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  // The first halo: eight times the ground points' mean spacing.
  const double area =
      std::max(1e-12, (tiles.max()[0] - tiles.min()[0]) * (tiles.max()[1] - tiles.min()[1]));
  const double first_halo =
      8.0 * std::sqrt(area / double(std::max<std::uint64_t>(1, ground_points)));
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<float> hag(points.size(), 0.0f);
    // The kept points in Morton order: each triangle search starts from the last one's.
    std::vector<std::uint32_t> pending;
    for (std::uint32_t i : spatialOrder(points)) {
      if (kept[i]) pending.push_back(i);
    }
    const double whole = tiles.max()[0] - tiles.min()[0] + 1.0;  // a halo that loads everything
    for (double halo = first_halo; !pending.empty();) {
      const double lo = tiles.lo(t) - halo, hi = tiles.hi(t) + halo;
      const bool everything = lo <= tiles.min()[0] && hi > tiles.max()[0];
      std::vector<std::array<double, 3>> ground = hull;
      for (std::size_t u = 0; u < tiles.tiles(); ++u) {
        if (tiles.hi(u) <= lo || tiles.lo(u) >= hi || tiles.count(u) == 0) continue;
        const std::vector<GridPoint> others = u == t ? points : tiles.readPoints(u);
        const std::vector<std::uint8_t> flags = groundFlags(tiles, u);
        for (std::size_t i = 0; i < others.size(); ++i) {
          if (flags[i] && others[i].x >= lo && others[i].x < hi) {
            ground.push_back({others[i].x, others[i].y, others[i].z});
          }
        }
      }
      const GroundTriangulation triangulation(ground, true);
      std::vector<std::uint32_t> again;
      // The next halo: the widest reach still pending (at least twice this one); everything at
      // once for a point outside the loaded ground's hull (only the whole ground answers it).
      double next = 2.0 * halo;
      for (std::uint32_t i : pending) {
        const GridPoint& q = points[i];
        const GroundTriangulation::Answer answer = triangulation.at(q.x, q.y);
        const auto [from, to] =
            std::isfinite(answer.radius)
                ? xRangeWithin(answer.centre_x, answer.centre_y, answer.radius, ground_box)
                : std::pair{-std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity()};
        // Every ground point that could be in the disc was loaded: x in [lo, hi).
        if (everything || from > to || (from >= lo && to < hi)) {
          hag[i] = float(q.z - answer.z);
        } else {
          again.push_back(i);
          const double need = std::max(to - tiles.hi(t), tiles.lo(t) - from);
          next = std::max(next, std::min(whole, 1.01 * need));
        }
      }
      pending = std::move(again);
      halo = next;
    }
    tiles.writeRecords<float>(t, heightAboveGroundScalar().name, hag);
    if (bar) bar->advance(points.size());
  }
}

StepScalar heightAboveGroundScalar() {
  return {"height_above_ground", ScalarType::Float32};
}

}  // namespace parallax
