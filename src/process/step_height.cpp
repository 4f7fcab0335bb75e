// --height-above-ground: each kept point's z less the ground's height under it, the ground being
// the 2D Delaunay triangulation of the ground points (terrain/ground_triangulation.h), out of
// core and within --memory. A tile's points are answered in groups (squares of the plane), each
// from a triangulation of the ground in a region around the group only; an answer whose disc
// (its triangle's circumcircle) reaches past the region it was answered from could differ from
// the whole ground's, and is asked again in a later round, from a region grown towards that disc
// by at most twice the last round's halo. So a triangulation holds a bounded patch of ground,
// not a slab and a halo as wide as the widest reach (terrain/NOTES.md, "Memory and time").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/bounds.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"
#include "terrain/ground_triangulation.h"

namespace parallax {

namespace {

constexpr std::uint8_t kGroundClass = 2;
constexpr double kHagInfinity = std::numeric_limits<double>::infinity();

std::vector<std::uint8_t> groundFlags(const TileSet& tiles, std::size_t t) {
  std::vector<std::uint8_t> flags = currentClasses(tiles, t);
  const std::vector<std::uint8_t> kept = tiles.readKept(t);
  for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = kept[i] && flags[i] == kGroundClass;
  return flags;
}

// A rectangle of the xy plane, [lo, hi) on each axis: the ground loaded for a group, or what an
// answer depends on. Infinite sides reach past every ground point.
struct HagRegion {
  double lo[2] = {kHagInfinity, kHagInfinity};
  double hi[2] = {-kHagInfinity, -kHagInfinity};

  bool holds(const HagRegion& inner) const {
    return inner.lo[0] >= lo[0] && inner.hi[0] < hi[0] && inner.lo[1] >= lo[1] &&
           inner.hi[1] < hi[1];
  }
  void unite(const HagRegion& other) {
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], other.lo[a]);
      hi[a] = std::max(hi[a], other.hi[a]);
    }
  }
};

// The bounding box of the part of the disc (cx, cy, r) inside the ground's bounding box: no
// ground point lies outside that box, so only the ground points in this rectangle could fall in
// the disc. False where the disc misses the box (the answer depends on no other point). Why it
// matters: the triangles along the hull's edges (the cloud's outer rows of ground points, nearly
// collinear) have circumcircles far wider than the cloud, centred outside it; inside the box
// they are a sliver along the edge, which a thin region holds.
bool discInsideGround(double cx, double cy, double r, const Bounds3& ground, HagRegion& out) {
  const double centre[2] = {cx, cy};
  for (int a = 0; a < 2; ++a) {
    const int b = 1 - a;
    double half = r;
    if (centre[b] < ground.min[b] || centre[b] > ground.max[b]) {
      const double d =
          centre[b] < ground.min[b] ? ground.min[b] - centre[b] : centre[b] - ground.max[b];
      if (!(d < r)) return false;
      half = std::sqrt((r - d) * (r + d));
    }
    out.lo[a] = std::max(centre[a] - half, ground.min[a]);
    out.hi[a] = std::min(centre[a] + half, ground.max[a]);
    if (out.lo[a] > out.hi[a]) return false;
  }
  return true;
}

// The ground points of a tile and a halo in x, bucketed in squares for a group's region: the
// groups of one tile load from here rather than from the tiles' files.
class SlabGround {
 public:
  // `points`: every ground point with x in [lo, hi) (infinite past the cloud's ends).
  SlabGround(std::vector<std::array<double, 3>> points, double lo, double hi, double cell)
      : lo_(lo), hi_(hi) {
    Bounds3 box;
    for (const auto& p : points) box.extend(p[0], p[1], p[2]);
    if (points.empty()) box.extend(0, 0, 0);
    x0_ = box.min[0], y0_ = box.min[1];
    // About four points a square at least, so that the index stays small beside the points.
    const double area = (box.max[0] - box.min[0]) * (box.max[1] - box.min[1]);
    cell_ = std::max({cell, std::sqrt(area / (double(points.size()) / 4.0 + 1.0)), 1e-9});
    nx_ = std::size_t((box.max[0] - x0_) / cell_) + 1;
    ny_ = std::size_t((box.max[1] - y0_) / cell_) + 1;
    start_.assign(nx_ * ny_ + 1, 0);
    for (const auto& p : points) ++start_[square(p[0], p[1]) + 1];
    for (std::size_t s = 1; s < start_.size(); ++s) start_[s] += start_[s - 1];
    points_.resize(points.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (const auto& p : points) points_[fill[square(p[0], p[1])]++] = p;
  }

  // Whether every ground point of `region` is here.
  bool covers(const HagRegion& region) const { return region.lo[0] >= lo_ && region.hi[0] <= hi_; }

  void appendIn(const HagRegion& region, std::vector<std::array<double, 3>>& out) const {
    const auto clampIndex = [](double v, std::size_t n) {
      return std::size_t(std::clamp(v, 0.0, double(n - 1)));
    };
    const std::size_t x_from = clampIndex((region.lo[0] - x0_) / cell_, nx_);
    const std::size_t x_to = clampIndex((region.hi[0] - x0_) / cell_, nx_);
    const std::size_t y_from = clampIndex((region.lo[1] - y0_) / cell_, ny_);
    const std::size_t y_to = clampIndex((region.hi[1] - y0_) / cell_, ny_);
    for (std::size_t y = y_from; y <= y_to; ++y) {
      for (std::size_t s = y * nx_ + x_from; s <= y * nx_ + x_to; ++s) {
        for (std::uint32_t i = start_[s]; i < start_[s + 1]; ++i) {
          const auto& p = points_[i];
          if (p[0] >= region.lo[0] && p[0] < region.hi[0] && p[1] >= region.lo[1] &&
              p[1] < region.hi[1]) {
            out.push_back(p);
          }
        }
      }
    }
  }

 private:
  std::size_t square(double x, double y) const {
    const std::size_t sx = std::min(nx_ - 1, std::size_t((x - x0_) / cell_));
    const std::size_t sy = std::min(ny_ - 1, std::size_t((y - y0_) / cell_));
    return sy * nx_ + sx;
  }

  double lo_, hi_;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  std::size_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_;
  std::vector<std::array<double, 3>> points_;
};

// Every ground point of the tiles with x in [lo, hi) and, where `region` is given, inside it.
void appendGroundFromTiles(const TileSet& tiles, double lo, double hi, const HagRegion* region,
                           std::vector<std::array<double, 3>>& out) {
  for (std::size_t u = 0; u < tiles.tiles(); ++u) {
    if (tiles.hi(u) <= lo || tiles.lo(u) >= hi || tiles.count(u) == 0) continue;
    const std::vector<GridPoint> points = tiles.readPoints(u);
    const std::vector<std::uint8_t> flags = groundFlags(tiles, u);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const GridPoint& p = points[i];
      if (!flags[i] || p.x < lo || p.x >= hi) continue;
      if (region && (p.y < region->lo[1] || p.y >= region->hi[1])) continue;
      out.push_back({p.x, p.y, p.z});
    }
  }
}

}  // namespace

void runHeightAboveGroundStep(const HeightAboveGroundStep&, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  if (!tiles.has(0, "class_in")) writeInputClasses(context);
  // The whole ground's convex hull (the hull of each tile's hull), added to every triangulation:
  // a point outside a group's triangulation is then outside the whole ground's, and answered by
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
  const double ground_area = std::max(
      1e-12, (ground_box.max[0] - ground_box.min[0]) * (ground_box.max[1] - ground_box.min[1]));
  const double density = double(std::max<std::uint64_t>(1, ground_points)) / ground_area;
  // The first halo: eight times the ground points' mean spacing (over the cloud's extent, as
  // before the groups, so that the rounds and their answers are those of earlier runs).
  const double area =
      std::max(1e-12, (tiles.max()[0] - tiles.min()[0]) * (tiles.max()[1] - tiles.min()[1]));
  const double spacing = std::sqrt(area / double(std::max<std::uint64_t>(1, ground_points)));
  const double first_halo = 8.0 * spacing;
  // A first round's group: a square holding about a quarter of a tile's points of ground, so that
  // a triangulation (about 200 bytes a point in CGAL) stays within a tile's share of --memory.
  const double target = double(std::max<std::uint64_t>(4096, context.max_tile_points / 4));
  const double first_square = std::sqrt(target / density);
  // The halo of ground held beside each tile for its groups (beyond it, a group reads the tiles'
  // files): 64 first halos, and no more ground than a tile's worth in it.
  const double ground_height = std::max(1e-12, ground_box.max[1] - ground_box.min[1]);
  const double held_halo =
      std::min(64.0 * first_halo, double(std::max<std::uint64_t>(1, context.max_tile_points)) /
                                      (2.0 * ground_height * density));
  // Past this halo every group loads the whole ground: an answer still pending then (none is
  // known) is settled by the whole triangulation.
  const double extent = std::max(tiles.max()[0] - tiles.min()[0], tiles.max()[1] - tiles.min()[1]);
  const double last_halo = 4.0 * extent + 4.0 * first_halo;

  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<float> hag(points.size(), 0.0f);
    // The kept points in Morton order: each triangle search starts from the last one's.
    // `pending` holds ranks in that order, so that sorting it restores the order.
    std::vector<std::uint32_t> morton;
    for (std::uint32_t i : spatialOrder(points)) {
      if (kept[i]) morton.push_back(i);
    }
    std::vector<std::uint32_t> pending(morton.size());
    for (std::size_t r = 0; r < pending.size(); ++r) pending[r] = std::uint32_t(r);
    if (pending.empty()) {
      tiles.writeRecords<float>(t, heightAboveGroundScalar().name, hag);
      continue;
    }
    const double held_lo = tiles.lo(t) - held_halo, held_hi = tiles.hi(t) + held_halo;
    std::vector<std::array<double, 3>> held_points;
    appendGroundFromTiles(tiles, held_lo, held_hi, nullptr, held_points);
    const SlabGround held(std::move(held_points), held_lo, held_hi, 4.0 * first_halo);
    // What each pending answer depended on last round (empty in the first: the point itself).
    std::vector<HagRegion> needs;
    for (double halo = first_halo; !pending.empty(); halo *= 2.0) {
      const bool everything = halo > last_halo;
      // Groups: squares of the plane (a first round's large; later ones about the halo's size,
      // the pending points being few and scattered), each in Morton order.
      const double side = halo == first_halo ? first_square : std::min(first_square, 4.0 * halo);
      std::vector<std::pair<std::uint64_t, std::uint32_t>> order(pending.size());
      for (std::size_t j = 0; j < pending.size(); ++j) {
        const GridPoint& q = points[morton[pending[j]]];
        const auto sx = std::uint64_t(std::max(0.0, (q.x - tiles.min()[0]) / side));
        const auto sy = std::uint64_t(std::max(0.0, (q.y - tiles.min()[1]) / side));
        order[j] = {(std::min<std::uint64_t>(sy, 0xffffffffu) << 32) |
                        std::min<std::uint64_t>(sx, 0xffffffffu),
                    std::uint32_t(j)};
      }
      std::sort(order.begin(), order.end());
      std::vector<std::uint32_t> again;
      std::vector<HagRegion> again_needs;
      for (std::size_t begin = 0; begin < order.size();) {
        std::size_t end = begin;
        while (end < order.size() && order[end].first == order[begin].first) ++end;
        // The group's region: around each point, its last need (and a spacing: the region is
        // half open) within the halo, and at least the first halo.
        HagRegion region;
        for (std::size_t k = begin; k < end; ++k) {
          const std::uint32_t j = order[k].second;
          const GridPoint& q = points[morton[pending[j]]];
          const double at[2] = {q.x, q.y};
          HagRegion around;
          for (int a = 0; a < 2; ++a) {
            const double need_lo = needs.empty() ? at[a] : needs[j].lo[a];
            const double need_hi = needs.empty() ? at[a] : needs[j].hi[a];
            around.lo[a] = std::min(at[a] - first_halo, std::max(need_lo - spacing, at[a] - halo));
            around.hi[a] = std::max(at[a] + first_halo, std::min(need_hi + spacing, at[a] + halo));
          }
          region.unite(around);
        }
        for (int a = 0; a < 2; ++a) {
          if (everything || region.lo[a] <= ground_box.min[a]) region.lo[a] = -kHagInfinity;
          if (everything || region.hi[a] > ground_box.max[a]) region.hi[a] = kHagInfinity;
        }
        std::vector<std::array<double, 3>> ground = hull;
        if (held.covers(region)) {
          held.appendIn(region, ground);
        } else {
          appendGroundFromTiles(tiles, region.lo[0], region.hi[0], &region, ground);
        }
        const GroundTriangulation triangulation(ground, true);
        ground = std::vector<std::array<double, 3>>();  // freed: `= {}` keeps the capacity
        for (std::size_t k = begin; k < end; ++k) {
          const std::uint32_t j = order[k].second;
          const GridPoint& q = points[morton[pending[j]]];
          const GroundTriangulation::Answer answer = triangulation.at(q.x, q.y);
          HagRegion need;
          bool exact = true;
          if (!std::isfinite(answer.radius)) {
            need.lo[0] = need.lo[1] = -kHagInfinity;
            need.hi[0] = need.hi[1] = kHagInfinity;
            exact = false;
          } else if (discInsideGround(answer.centre_x, answer.centre_y, answer.radius, ground_box,
                                      need)) {
            // Every ground point that could be in the disc was loaded.
            exact = region.holds(need);
          }
          if (exact) {
            hag[morton[pending[j]]] = float(q.z - answer.z);
          } else {
            again.push_back(pending[j]);
            again_needs.push_back(need);
          }
        }
        begin = end;
      }
      // Back in Morton order for the next round's groups.
      std::vector<std::size_t> back(again.size());
      for (std::size_t k = 0; k < back.size(); ++k) back[k] = k;
      std::sort(back.begin(), back.end(),
                [&](std::size_t a, std::size_t b) { return again[a] < again[b]; });
      pending.clear();
      needs.clear();
      pending.reserve(again.size());
      for (std::size_t k : back) {
        pending.push_back(again[k]);
        needs.push_back(again_needs[k]);
      }
    }
    tiles.writeRecords<float>(t, heightAboveGroundScalar().name, hag);
    if (bar) bar->advance(points.size());
  }
}

StepScalar heightAboveGroundScalar() {
  return {"height_above_ground", ScalarType::Float32};
}

}  // namespace parallax
