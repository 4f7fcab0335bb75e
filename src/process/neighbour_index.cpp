// NeighbourIndex (neighbour_index.h): a bounding-volume tree over the points in Morton order,
// searched with exact, (d2, id)-ordered result sets.
#include "process/neighbour_index.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_set>
#include <utility>

#include "core/morton.h"

namespace parallax {

namespace {

constexpr std::int64_t kMaxCells = (std::int64_t(1) << 21) - 1;  // 21 bits a coordinate
constexpr double kInf = std::numeric_limits<double>::infinity();

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

// Morton keys of the points over their bounds (x in bit 0, y in bit 1, z in bit 2 of each
// triple), sorted, ties by index.
std::vector<std::pair<std::uint64_t, std::uint32_t>> sortedMortonKeys(
    std::span<const GridPoint> points) {
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
  // The keys are distinct pairs, so any sort gives the same order; the parallel one uses both
  // cores on the largest tiles.
  tbb::parallel_sort(keyed.begin(), keyed.end());
  return keyed;
}

// The smallest squared distance from q to a point in [lo, hi], in squaredDistance's expression.
// Rounded subtraction, multiplication and addition are monotonic, so for every point p in the
// box this is <= squaredDistance(q, p) as computed: pruning a node whose bound exceeds the K-th
// distance never drops a point that belongs to the answer, ties included.
inline double boxDistance2(const double lo[3], const double hi[3], double x, double y, double z) {
  const double dx = x < lo[0] ? lo[0] - x : (x > hi[0] ? x - hi[0] : 0.0);
  const double dy = y < lo[1] ? lo[1] - y : (y > hi[1] ? y - hi[1] : 0.0);
  const double dz = z < lo[2] ? lo[2] - z : (z > hi[2] ? z - hi[2] : 0.0);
  return (dx * dx + dy * dy) + dz * dz;
}

}  // namespace

std::vector<std::uint32_t> spatialOrder(std::span<const GridPoint> points) {
  const std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed = sortedMortonKeys(points);
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// A binary tree of boxes over the points in Morton order (a "linear BVH", Lauterbach et al.
// 2009): a node is a run of consecutive points, split where the first Morton bit that differs
// across the run changes, which is a k-d split at a power-of-two midpoint; each node keeps the
// tight box of its points. Building is a sort and a linear pass (nanoflann's median splits spent
// 14 % of a 2 M-point normals run there, on one core); the points are stored in the tree's order,
// so a leaf's points are adjacent in memory and a query walks memory that the previous query (in
// Morton order too) left in cache. Nodes are laid out depth first, the left child right after
// its parent.
struct NeighbourIndex::Tree {
  // Measured (NOTES.md, "larger leaves"): 48 took 15 % less CPU than 12 on 2 M points, K = 16
  // (and radius queries 11 % less); 32 and 64 were between. A leaf's points are adjacent in
  // memory: scanning a few more beats walking more nodes.
  static constexpr std::uint32_t kLeafPoints = 48;
  static constexpr std::uint32_t kLeaf = std::numeric_limits<std::uint32_t>::max();
  struct Node {
    double lo[3], hi[3];
    std::uint32_t begin, end;  // the node's points: ordered[begin, end)
    std::uint32_t right;       // the right child's index (the left one is this + 1); kLeaf
  };
  std::vector<GridPoint> ordered;    // the points in Morton order
  std::vector<std::uint32_t> given;  // ordered[i] is points[given[i]]
  std::vector<Node> nodes;

  explicit Tree(const std::vector<GridPoint>& points) {
    const std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed = sortedMortonKeys(points);
    given.resize(points.size());
    ordered.resize(points.size());
    std::vector<std::uint64_t> keys(points.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
      given[i] = keyed[i].second;
      keys[i] = keyed[i].first;
      ordered[i] = points[given[i]];
    }
    nodes.reserve(2 * (points.size() / (kLeafPoints / 2) + 1));
    build(keys, 0, std::uint32_t(points.size()));
  }

  std::uint32_t build(const std::vector<std::uint64_t>& keys, std::uint32_t begin,
                      std::uint32_t end) {
    const std::uint32_t at = std::uint32_t(nodes.size());
    nodes.push_back({{0, 0, 0}, {0, 0, 0}, begin, end, kLeaf});
    if (end - begin <= kLeafPoints) {
      Node& leaf = nodes[at];
      for (int a = 0; a < 3; ++a) leaf.lo[a] = leaf.hi[a] = (&ordered[begin].x)[a];
      for (std::uint32_t i = begin + 1; i < end; ++i) {
        for (int a = 0; a < 3; ++a) {
          leaf.lo[a] = std::min(leaf.lo[a], (&ordered[i].x)[a]);
          leaf.hi[a] = std::max(leaf.hi[a], (&ordered[i].x)[a]);
        }
      }
      return at;
    }
    const std::uint64_t differ = keys[begin] ^ keys[end - 1];
    std::uint32_t middle = begin + (end - begin) / 2;  // equal keys: halve the run
    if (differ != 0) {
      // The keys are sorted and agree above the highest differing bit: the run splits where
      // that bit turns to 1.
      const std::uint64_t bit = std::uint64_t(1) << (63 - std::countl_zero(differ));
      middle =
          std::uint32_t(std::partition_point(keys.begin() + begin, keys.begin() + end,
                                             [&](std::uint64_t key) { return (key & bit) == 0; }) -
                        keys.begin());
    }
    const std::uint32_t left = build(keys, begin, middle);
    const std::uint32_t right = build(keys, middle, end);
    Node& node = nodes[at];
    node.right = right;
    for (int a = 0; a < 3; ++a) {
      node.lo[a] = std::min(nodes[left].lo[a], nodes[right].lo[a]);
      node.hi[a] = std::max(nodes[left].hi[a], nodes[right].hi[a]);
    }
    return at;
  }

  // Visits the leaves whose boxes lie within `bound()` of q (re-read after every leaf: the
  // K-nearest search narrows it), nearer child first.
  template <class Bound, class Visit>
  void search(double x, double y, double z, Bound&& bound, Visit&& visit) const {
    struct Pending {
      std::uint32_t node;
      double d2;
    };
    Pending stack[128];  // depth <= 64 Morton bits + log2(points): at most one pending a level
    int top = 0;
    stack[top++] = {0, boxDistance2(nodes[0].lo, nodes[0].hi, x, y, z)};
    while (top > 0) {
      const Pending p = stack[--top];
      if (p.d2 > bound()) continue;
      std::uint32_t at = p.node;
      while (nodes[at].right != kLeaf) {
        const std::uint32_t left = at + 1, right = nodes[at].right;
        const double dl = boxDistance2(nodes[left].lo, nodes[left].hi, x, y, z);
        const double dr = boxDistance2(nodes[right].lo, nodes[right].hi, x, y, z);
        const double worst = bound();
        if (dl <= dr) {
          if (dr <= worst) stack[top++] = {right, dr};
          if (dl > worst) break;
          at = left;
        } else {
          if (dl <= worst) stack[top++] = {left, dl};
          if (dr > worst) break;
          at = right;
        }
      }
      if (nodes[at].right == kLeaf) visit(nodes[at].begin, nodes[at].end);
    }
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

std::span<const GridPoint> NeighbourIndex::treePoints() const {
  if (!tree_) return {};
  return tree_->ordered;
}

std::span<const std::uint32_t> NeighbourIndex::treeOrder() const {
  if (!tree_) return {};
  return tree_->given;
}

void NeighbourIndex::nearest(double x, double y, double z, std::size_t k,
                             std::vector<Neighbour>& out) const {
  if (k == 0 || !tree_) {
    out.clear();
    return;
  }
  // `out` is kept sorted by (d2, id), at most k long: K is small (8-32 for normals and
  // outliers), where an insertion into a sorted array beats a heap and leaves nothing to sort.
  const std::vector<GridPoint>& ordered = tree_->ordered;
  const std::vector<std::uint32_t>& given = tree_->given;
  // k distinct points of the index lie within `worst` of the query (the squared distance of the
  // farthest, in the same expression as every other), so the K-th nearest does too, and every
  // point of the answer, ties at the K-th distance included: starting the search with this
  // bound drops nothing the answer holds. A consecutive query in Morton order is near: the
  // bound is tight.
  double worst = kInf;
  if (out.size() == k) {
    double bound = 0.0;
    for (const Neighbour& n : out) {
      if (n.in_tree >= ordered.size() || ordered[n.in_tree].id != n.id) {
        bound = kInf;  // not this index's answer
        break;
      }
      const GridPoint& p = ordered[n.in_tree];
      bound = std::max(bound, squaredDistance(x, y, z, p.x, p.y, p.z));
    }
    worst = bound;
  }
  // The K best so far in out[0, size), sorted by (d2, id); `at` (an index into points()) is
  // looked up once for each of the k that remain, not for every point that entered on the way.
  out.resize(k);
  std::size_t size = 0;
  tree_->search(
      x, y, z, [&] { return worst; },
      [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t i = begin; i < end; ++i) {
          const GridPoint& p = ordered[i];
          const double d2 = squaredDistance(x, y, z, p.x, p.y, p.z);
          if (d2 > worst) continue;
          const Neighbour n{d2, 0, p.id, i};
          std::size_t at = size;
          if (size == k) {
            if (!(n < out[k - 1])) continue;
            at = k - 1;
          } else {
            ++size;
          }
          while (at > 0 && n < out[at - 1]) {
            out[at] = out[at - 1];
            --at;
          }
          out[at] = n;
          if (size == k) worst = out[k - 1].d2;
        }
      });
  out.resize(size);
  for (Neighbour& n : out) n.at = given[n.in_tree];
}

void NeighbourIndex::withinRadius(double x, double y, double z, double radius,
                                  std::vector<Neighbour>& out) const {
  out.clear();
  if (!tree_ || !(radius >= 0.0)) return;
  const double r2 = radius * radius;
  const std::vector<GridPoint>& ordered = tree_->ordered;
  const std::vector<std::uint32_t>& given = tree_->given;
  tree_->search(
      x, y, z, [&] { return r2; },
      [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t i = begin; i < end; ++i) {
          const GridPoint& p = ordered[i];
          const double d2 = squaredDistance(x, y, z, p.x, p.y, p.z);
          if (d2 <= r2) out.push_back({d2, given[i], p.id, i});
        }
      });
  std::sort(out.begin(), out.end());
}

}  // namespace parallax
