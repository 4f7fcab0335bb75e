// Exact nearest-neighbour queries over the points of one tile: a uniform grid of cells, the
// points sorted by cell, cells found through an open-addressing table.
//
// Results are exact and fully determined: neighbours are ordered by (squared distance, id), so a
// tie at the K-th distance is broken by the smaller id whatever the grid's cell size or the
// points around. This is what makes a tiled run give the same bytes as an untiled one
// (NOTES.md). Positions are world coordinates in double; the squared distance of two points is
// computed as (dx*dx + dy*dy) + dz*dz, the same expression everywhere.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace parallax {

struct GridPoint {
  double x, y, z;
  std::uint64_t id;  // the point's index in the whole cloud (unique)
};

struct Neighbour {
  double d2;         // squared distance to the query
  std::uint32_t at;  // index into the grid's points()
  std::uint64_t id;  // the point's id
  friend bool operator<(const Neighbour& a, const Neighbour& b) {
    return a.d2 < b.d2 || (a.d2 == b.d2 && a.id < b.id);
  }
};

inline double squaredDistance(double ax, double ay, double az, double bx, double by, double bz) {
  const double dx = ax - bx, dy = ay - by, dz = az - bz;
  return (dx * dx + dy * dy) + dz * dz;
}

class NeighbourGrid {
 public:
  // Takes the points (any order); `cell` > 0 is the cell edge in world units.
  NeighbourGrid(std::vector<GridPoint> points, double cell);

  // A cell edge for K-nearest queries over `points`: about `per_cell` points per occupied cell.
  static double cellForDensity(std::span<const GridPoint> points, double per_cell);

  // The points, sorted by cell (the order `Neighbour::at` refers to).
  const std::vector<GridPoint>& points() const { return points_; }

  // The k nearest points to (x, y, z) (the point itself included when it is in the grid), in
  // (d2, id) order, into `out` (fewer when the grid holds fewer). `out` is reused storage.
  void nearest(double x, double y, double z, std::size_t k, std::vector<Neighbour>& out) const;

  // Every point within `radius` (d2 <= radius^2), in (d2, id) order.
  void withinRadius(double x, double y, double z, double radius, std::vector<Neighbour>& out) const;

 private:
  struct Cell {
    std::uint64_t key;
    std::uint32_t begin, end;
  };
  std::uint64_t keyOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  std::int64_t cellCoord(int axis, double v) const;
  const Cell* find(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;

  std::vector<GridPoint> points_;
  double cell_ = 1.0;
  double origin_[3] = {0, 0, 0};
  std::int64_t extent_[3] = {1, 1, 1};  // cells along each axis
  std::vector<Cell> table_;             // open addressing, key UINT64_MAX: empty
  std::uint64_t mask_ = 0;
};

}  // namespace parallax
