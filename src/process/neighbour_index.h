// Exact nearest-neighbour queries over the points of one tile: a tree of boxes over the points in
// Morton order, of the project's own, searched with result sets ordered by (distance, id).
// Chosen on measurement (NOTES.md): a uniform grid does not follow scans' density, which varies
// by orders of magnitude; nanoflann's k-d tree (Debian's libnanoflann-dev) does, and this tree
// does too, built in a sort and a linear pass instead of median splits, and searched over
// points adjacent in memory.
//
// Results are exact and fully determined: neighbours are ordered by (squared distance, id), so a
// tie at the K-th distance is broken by the smaller id whatever the grid's cell size or the
// points around. This is what makes a tiled run give the same bytes as an untiled one
// (NOTES.md). Positions are world coordinates in double; the squared distance of two points is
// computed as (dx*dx + dy*dy) + dz*dz, the same expression everywhere.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace parallax {

struct GridPoint {
  double x, y, z;
  std::uint64_t id;  // the point's index in the whole cloud (unique)
};

struct Neighbour {
  double d2;              // squared distance to the query
  std::uint32_t at;       // index into NeighbourIndex::points()
  std::uint64_t id;       // the point's id
  std::uint32_t in_tree;  // index into NeighbourIndex::treePoints(): the same point
  friend bool operator<(const Neighbour& a, const Neighbour& b) {
    return a.d2 < b.d2 || (a.d2 == b.d2 && a.id < b.id);
  }
};

inline double squaredDistance(double ax, double ay, double az, double bx, double by, double bz) {
  const double dx = ax - bx, dy = ay - by, dz = az - bz;
  return (dx * dx + dy * dy) + dz * dz;
}

// The indices of `points` in Morton order (z-order of their positions over their bounds, 21 bits
// an axis; ties by index). Queries asked in this order search the same part of a tree one after
// another, which then stays in cache: asked in the input's order they spent most of their time
// waiting for memory. Each answer is the same in any order.
std::vector<std::uint32_t> spatialOrder(std::span<const GridPoint> points);

class NeighbourIndex {
 public:
  // Takes the points (any order; `Neighbour::at` indexes them as given).
  explicit NeighbourIndex(std::vector<GridPoint> points);
  ~NeighbourIndex();
  NeighbourIndex(const NeighbourIndex&) = delete;
  NeighbourIndex& operator=(const NeighbourIndex&) = delete;

  // About the radius within which a point of `points` has `count` neighbours, from the points
  // per occupied cell of a sample (a first halo for K-nearest queries; never needed exactly).
  static double radiusForCount(std::span<const GridPoint> points, double count);

  const std::vector<GridPoint>& points() const { return points_; }
  // The same points in the tree's order (Morton order): the neighbours of one query, and of the
  // queries asked before it in Morton order, lie close together here, where points() scatters
  // them over the tile (what a loop over every neighbour's position should read).
  std::span<const GridPoint> treePoints() const;
  // For each of treePoints(), its index in points(): treePoints()[j] is points()[treeOrder()[j]].
  std::span<const std::uint32_t> treeOrder() const;

  // The k nearest points to (x, y, z) (the point itself included when it is indexed), in
  // (d2, id) order, into `out` (fewer when there are fewer). `out` is reused storage: when it
  // holds k distinct points of this index (the answer of the query asked before, checked by
  // their ids), the farthest of them from (x, y, z) bounds the search from its start, which
  // prunes what a search without a bound visits before it has k points. The answer is the same.
  void nearest(double x, double y, double z, std::size_t k, std::vector<Neighbour>& out) const;

  // Every point within `radius` (d2 <= radius^2), in (d2, id) order.
  void withinRadius(double x, double y, double z, double radius, std::vector<Neighbour>& out) const;

 private:
  struct Tree;
  std::vector<GridPoint> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace parallax
