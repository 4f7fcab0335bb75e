// NeighbourIndex (neighbour_index.h): nanoflann's k-d tree with exact, (d2, id)-ordered
// result sets.
#include "process/neighbour_index.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_set>
#include <utility>

#include "core/morton.h"

namespace parallax {

namespace {

constexpr std::int64_t kMaxCells = (std::int64_t(1) << 21) - 1;  // 21 bits a coordinate

struct Box {
  double min[3] = {0, 0, 0}, max[3] = {0, 0, 0};
};

Box boxOf(std::span<const GridPoint> points) {
  Box box;
  if (points.empty()) return box;
  for (int a = 0; a < 3; ++a) box.min[a] = box.max[a] = (&points[0].x)[a];
  for (const GridPoint& p : points) {
    for (int a = 0; a < 3; ++a) {
      box.min[a] = std::min(box.min[a], (&p.x)[a]);
      box.max[a] = std::max(box.max[a], (&p.x)[a]);
    }
  }
  return box;
}

// nanoflann's view of the points.
struct PointsAdaptor {
  const std::vector<GridPoint>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t axis) const { return (&(*points)[i].x)[axis]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                        PointsAdaptor, 3, std::uint32_t>;

// The search prunes with worstDist(); a hair above the true worst distance keeps the points tied
// with it (and any the tree's rounded bounds would cut) in play, and addPoint decides by the
// exact (d2, id) order. nanoflann's own KNN set breaks ties by the tree's order, which depends
// on the other points of the tile: the tiled and untiled runs would differ.
constexpr double kMargin = 1.0 + 1e-9;

// The result sets see the tree's copy of the points (in leaf order) and report each as the
// caller's index through `given`.
struct NearestSet {
  const std::vector<GridPoint>* points;
  const std::vector<std::uint32_t>* given;
  double q[3];
  std::size_t k;
  std::vector<Neighbour>* heap;
  double worst = std::numeric_limits<double>::infinity();
  double worstDist() const { return worst; }
  bool full() const { return heap->size() == k; }
  bool addPoint(double, std::uint32_t at) {
    const GridPoint& p = (*points)[at];
    const Neighbour n{squaredDistance(q[0], q[1], q[2], p.x, p.y, p.z), (*given)[at], p.id};
    std::vector<Neighbour>& h = *heap;
    if (h.size() < k) {
      h.push_back(n);
      std::push_heap(h.begin(), h.end());
    } else if (n < h.front()) {
      std::pop_heap(h.begin(), h.end());
      h.back() = n;
      std::push_heap(h.begin(), h.end());
    }
    if (h.size() == k) worst = h.front().d2 * kMargin + std::numeric_limits<double>::min();
    return true;
  }
};

struct RadiusSet {
  const std::vector<GridPoint>* points;
  const std::vector<std::uint32_t>* given;
  double q[3];
  double r2;
  std::vector<Neighbour>* out;
  double worstDist() const { return r2 * kMargin + std::numeric_limits<double>::min(); }
  bool full() const { return true; }
  bool addPoint(double, std::uint32_t at) {
    const GridPoint& p = (*points)[at];
    const double d2 = squaredDistance(q[0], q[1], q[2], p.x, p.y, p.z);
    if (d2 <= r2) out->push_back({d2, (*given)[at], p.id});
    return true;
  }
};

}  // namespace

std::vector<std::uint32_t> spatialOrder(std::span<const GridPoint> points) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (const GridPoint& p : points) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], (&p.x)[a]);
      hi[a] = std::max(hi[a], (&p.x)[a]);
    }
  }
  double scale[3];
  for (int a = 0; a < 3; ++a) scale[a] = hi[a] > lo[a] ? 2097151.0 / (hi[a] - lo[a]) : 0.0;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double cell = ((&points[i].x)[a] - lo[a]) * scale[a];
      key |= spreadBits21(std::uint64_t(std::clamp(cell, 0.0, 2097151.0))) << a;
    }
    keyed[i] = {key, std::uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// The tree is built over the points as given, then searched over a copy of them in its leaves'
// order: a leaf's points are then adjacent in memory, where the given order scatters them over
// the tile (a search touches a few leaves and every point in them; most of its time went to
// cache misses). The same tree, the same distances: the same answers, a few times faster.
struct NeighbourIndex::Tree {
  std::vector<GridPoint> ordered;    // the points in leaf order
  std::vector<std::uint32_t> given;  // ordered[i] is points[given[i]]
  PointsAdaptor adaptor;
  KdTree tree;
  explicit Tree(const std::vector<GridPoint>& points)
      : adaptor{&points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    tree.buildIndex();
    given.assign(tree.vAcc.begin(), tree.vAcc.end());
    ordered.resize(points.size());
    for (std::size_t i = 0; i < given.size(); ++i) {
      ordered[i] = points[given[i]];
      tree.vAcc[i] = std::uint32_t(i);
    }
    adaptor.points = &ordered;
  }
};

double NeighbourIndex::radiusForCount(std::span<const GridPoint> points, double per_cell) {
  if (points.size() < 2) return 1.0;
  const Box box = boxOf(points);
  double extent[3], volume = 1.0, largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    extent[a] = box.max[a] - box.min[a];
    largest = std::max(largest, extent[a]);
  }
  if (largest <= 0.0) return 1.0;  // every point at one place
  for (int a = 0; a < 3; ++a) volume *= std::max(extent[a], largest * 1e-3);
  const double n = double(points.size());
  double cell = std::cbrt(volume * per_cell / n);
  // Scans are surfaces, not volumes: refine on a sample by the points per occupied cell, which
  // on a surface grows with the square of the cell.
  const std::size_t step = std::max<std::size_t>(1, points.size() / 100000);
  const double sample = double((points.size() + step - 1) / step);
  for (int round = 0; round < 8; ++round) {
    std::unordered_set<std::uint64_t> occupied;
    occupied.reserve(std::size_t(sample));
    for (std::size_t i = 0; i < points.size(); i += step) {
      std::uint64_t key = 0;
      for (int a = 0; a < 3; ++a) {
        key = key * 2097152u + std::uint64_t(((&points[i].x)[a] - box.min[a]) / cell);
      }
      occupied.insert(key);
    }
    const double per_sampled_cell = sample / double(occupied.size());
    const double estimate = n / double(occupied.size());
    if (per_sampled_cell < 2.0 || (estimate < 2.0 * per_cell && estimate > 0.5 * per_cell)) break;
    cell *= std::sqrt(per_cell / estimate);
  }
  return std::max(cell, largest / double(kMaxCells - 1));
}

NeighbourIndex::NeighbourIndex(std::vector<GridPoint> points) : points_(std::move(points)) {
  assert(points_.size() < std::numeric_limits<std::uint32_t>::max() &&
         "NeighbourIndex: at most 2^32 - 1 points");
  if (!points_.empty()) tree_ = std::make_unique<Tree>(points_);
}

NeighbourIndex::~NeighbourIndex() = default;

void NeighbourIndex::nearest(double x, double y, double z, std::size_t k,
                             std::vector<Neighbour>& out) const {
  out.clear();
  if (k == 0 || !tree_) return;
  NearestSet set{&tree_->ordered, &tree_->given, {x, y, z}, k, &out};
  const double q[3] = {x, y, z};
  tree_->tree.findNeighbors(set, q, nanoflann::SearchParams());
  std::sort(out.begin(), out.end());
}

void NeighbourIndex::withinRadius(double x, double y, double z, double radius,
                                  std::vector<Neighbour>& out) const {
  out.clear();
  if (!tree_ || !(radius >= 0.0)) return;
  RadiusSet set{&tree_->ordered, &tree_->given, {x, y, z}, radius * radius, &out};
  const double q[3] = {x, y, z};
  tree_->tree.findNeighbors(set, q, nanoflann::SearchParams());
  std::sort(out.begin(), out.end());
}

}  // namespace parallax
