// alignPointToPlane and estimateNormals (point_to_plane_icp.h).
#include "registration/point_to_plane_icp.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "process/local_plane.h"
#include "process/neighbour_index.h"

namespace parallax {

namespace {

// Pairs are summed a block at a time, then the blocks in order: the same sums whatever the
// threads did.
constexpr std::size_t kBlock = 4096;
// Fewer pairs than this cannot fix six unknowns with any margin.
constexpr std::uint64_t kLeastPairs = 6;
// A coarse level reduced to fewer points than this says little about the shape: skipped.
constexpr std::size_t kLeastLevelPoints = 256;

struct NormalEquations {
  double a[6][6] = {};
  double b[6] = {};
  double squared = 0.0;  // sum of squared point-to-point distances of the pairs
  std::uint64_t pairs = 0;

  void add(const NormalEquations& o) {
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) a[i][j] += o.a[i][j];
      b[i] += o.b[i];
    }
    squared += o.squared;
    pairs += o.pairs;
  }
};

std::vector<GridPoint> gridPoints(std::span<const Point3> points) {
  std::vector<GridPoint> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = {points[i][0], points[i][1], points[i][2], i};
  return out;
}

// Every source point moved by `t`, paired with its nearest target point within max_distance:
// the point-to-plane normal equations (with `normals`), or only the distances when `normals` is
// empty.
NormalEquations pairUp(std::span<const Point3> source, const RigidTransform& t,
                       const NeighbourIndex& target, std::span<const Point3> normals,
                       double max_distance) {
  const std::size_t blocks = (source.size() + kBlock - 1) / kBlock;
  std::vector<NormalEquations> partial(blocks);
  const double max2 = max_distance * max_distance;
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    NormalEquations& e = partial[block];
    std::vector<Neighbour> found;
    const std::size_t end = std::min(source.size(), (block + 1) * kBlock);
    for (std::size_t i = block * kBlock; i < end; ++i) {
      const Point3 p = t.apply(source[i]);
      target.nearest(p[0], p[1], p[2], 1, found);
      if (found.empty() || found[0].d2 > max2) continue;
      ++e.pairs;
      e.squared += found[0].d2;
      if (normals.empty()) continue;
      const Point3& n = normals[found[0].at];
      if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) continue;
      const GridPoint& q = target.points()[found[0].at];
      const double r = (p[0] - q.x) * n[0] + (p[1] - q.y) * n[1] + (p[2] - q.z) * n[2];
      const double j[6] = {p[1] * n[2] - p[2] * n[1],
                           p[2] * n[0] - p[0] * n[2],
                           p[0] * n[1] - p[1] * n[0],
                           n[0],
                           n[1],
                           n[2]};
      for (int x = 0; x < 6; ++x) {
        for (int y = x; y < 6; ++y) e.a[x][y] += j[x] * j[y];
        e.b[x] += j[x] * r;
      }
    }
  });
  NormalEquations total;
  for (const NormalEquations& e : partial) total.add(e);
  for (int x = 0; x < 6; ++x) {
    for (int y = 0; y < x; ++y) total.a[x][y] = total.a[y][x];
  }
  return total;
}

// Solves A x = -b by Cholesky, A damped by a millionth of a millionth of its mean diagonal so a
// direction the geometry leaves free (a plane slides in itself) stays put instead of failing.
bool solve6(const NormalEquations& e, double x[6]) {
  double l[6][6] = {};
  double trace = 0.0;
  for (int i = 0; i < 6; ++i) trace += e.a[i][i];
  const double damping = 1e-12 * trace / 6.0;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j <= i; ++j) {
      double sum = e.a[i][j] + (i == j ? damping : 0.0);
      for (int k = 0; k < j; ++k) sum -= l[i][k] * l[j][k];
      if (i == j) {
        if (!(sum > 0.0)) return false;
        l[i][i] = std::sqrt(sum);
      } else {
        l[i][j] = sum / l[j][j];
      }
    }
  }
  double y[6];
  for (int i = 0; i < 6; ++i) {
    double sum = -e.b[i];
    for (int k = 0; k < i; ++k) sum -= l[i][k] * y[k];
    y[i] = sum / l[i][i];
  }
  for (int i = 5; i >= 0; --i) {
    double sum = y[i];
    for (int k = i + 1; k < 6; ++k) sum -= l[k][i] * x[k];
    x[i] = sum / l[i][i];
  }
  return true;
}

// The centroids of the points in each occupied voxel of edge `size`, voxels in key order and
// points in index order (the same centroids every run).
std::vector<Point3> voxelCentroids(std::span<const Point3> points, double size) {
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;
  std::vector<std::pair<Key, std::size_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    keyed[i] = {{std::int64_t(std::floor(points[i][0] / size)),
                 std::int64_t(std::floor(points[i][1] / size)),
                 std::int64_t(std::floor(points[i][2] / size))},
                i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Point3> out;
  for (std::size_t i = 0; i < keyed.size();) {
    Point3 sum = {0, 0, 0};
    std::size_t j = i;
    for (; j < keyed.size() && keyed[j].first == keyed[i].first; ++j) {
      for (int a = 0; a < 3; ++a) sum[std::size_t(a)] += points[keyed[j].second][std::size_t(a)];
    }
    const double n = double(j - i);
    out.push_back({sum[0] / n, sum[1] / n, sum[2] / n});
    i = j;
  }
  return out;
}

}  // namespace

std::vector<Point3> estimateNormals(std::span<const Point3> points, std::uint32_t k) {
  const NeighbourIndex index(gridPoints(points));
  std::vector<Point3> normals(points.size(), Point3{0, 0, 0});
  const std::vector<std::uint32_t> order = spatialOrder(index.points());
  tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t j) {
    const std::size_t i = order[j];
    thread_local std::vector<Neighbour> found;
    index.nearest(points[i][0], points[i][1], points[i][2], k, found);
    const LocalPlane plane = fitLocalPlane(index.points(), found);
    if (plane.valid) normals[i] = {plane.normal[0], plane.normal[1], plane.normal[2]};
  });
  return normals;
}

IcpResult alignPointToPlane(std::span<const Point3> source, std::span<const Point3> target,
                            std::span<const Point3> target_normals, const IcpOptions& options) {
  if (source.empty() || target.empty()) {
    throw std::invalid_argument("register: an empty cloud (source or target has no point)");
  }
  if (!target_normals.empty() && target_normals.size() != target.size()) {
    throw std::invalid_argument("register: target normals and points differ in count");
  }
  if (options.levels == 0 || options.max_iterations == 0 || options.normal_k < 3 ||
      !(options.max_distance >= 0.0)) {
    throw std::invalid_argument(
        "register: levels and iterations must be at least 1, normal K at least 3, the maximum "
        "distance not negative");
  }
  // The local origin: the target's bounds' centre. Subtracting it is exact for coordinates of
  // similar magnitude (Sterbenz), and squares of local coordinates keep their digits.
  Point3 lo = target[0], hi = target[0];
  for (const Point3& p : target) {
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  const Point3 origin = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  const double diagonal =
      std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  auto local = [&](std::span<const Point3> points) {
    std::vector<Point3> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (std::size_t a = 0; a < 3; ++a) out[i][a] = points[i][a] - origin[a];
    }
    return out;
  };
  const std::vector<Point3> dst = local(target);
  // The source in Morton order: consecutive queries then walk the same part of the k-d tree,
  // which stays in cache (process/NOTES.md measured 1.7x on normals). Sums change order, not
  // what they sum.
  std::vector<Point3> src = local(source);
  {
    const std::vector<std::uint32_t> order = spatialOrder(gridPoints(src));
    std::vector<Point3> sorted(src.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = src[order[i]];
    src = std::move(sorted);
  }
  const std::vector<Point3> normals =
      target_normals.empty() ? estimateNormals(dst, options.normal_k)
                             : std::vector<Point3>(target_normals.begin(), target_normals.end());
  const NeighbourIndex index(gridPoints(dst));
  IcpResult result;
  result.max_distance = options.max_distance > 0.0 ? options.max_distance : diagonal / 20.0;
  const RigidTransform to_local = RigidTransform::translation(-origin[0], -origin[1], -origin[2]);
  const RigidTransform to_world = RigidTransform::translation(origin[0], origin[1], origin[2]);
  RigidTransform t = to_local * options.init * to_world;
  const double spacing = NeighbourIndex::radiusForCount(index.points(), 4.0);
  // Converged when a step moves every point by less than this (a micrometre on a 1 km cloud).
  // Not finer: near the optimum the nearest-neighbour pairs keep changing by a few points a step,
  // and the steps that follow stay above a nanometre. At 1e-12 of the diagonal two 10 M-point
  // terrains ran 206 iterations for what Open3D found in one level's worth (registration NOTES).
  const double still = 1e-9 * std::max(diagonal, 1.0);
  for (std::uint32_t level = options.levels; level-- > 0;) {
    std::vector<Point3> reduced;
    std::span<const Point3> points(src);
    if (level > 0) {
      reduced = voxelCentroids(src, spacing * double(1u << level));
      if (reduced.size() < kLeastLevelPoints) continue;
      points = reduced;
    }
    for (std::uint32_t iteration = 0; iteration < options.max_iterations; ++iteration) {
      const NormalEquations e = pairUp(points, t, index, normals, result.max_distance);
      double x[6];
      if (e.pairs < kLeastPairs || !solve6(e, x)) {
        throw RegistrationError(
            "no overlap: " + std::to_string(e.pairs) + " of " + std::to_string(points.size()) +
            " source points lie within " + std::to_string(result.max_distance) +
            " of the target where the transform puts them (give --init, or a larger "
            "--max-distance)");
      }
      const RigidTransform step = RigidTransform::translation(x[3], x[4], x[5]) *
                                  RigidTransform::fromEuler(x[0], x[1], x[2]);
      t = step * t;
      ++result.iterations;
      const double angle = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      const double move = std::sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5]);
      if (angle * diagonal + move < still) break;
    }
  }
  const NormalEquations final_pairs = pairUp(src, t, index, {}, result.max_distance);
  if (final_pairs.pairs < kLeastPairs) {
    throw RegistrationError("no overlap: " + std::to_string(final_pairs.pairs) +
                            " source points within " + std::to_string(result.max_distance) +
                            " of the target after alignment");
  }
  result.correspondences = final_pairs.pairs;
  result.rms = std::sqrt(final_pairs.squared / double(final_pairs.pairs));
  result.overlap = double(final_pairs.pairs) / double(src.size());
  result.transform = to_world * t * to_local;
  return result;
}

}  // namespace parallax
