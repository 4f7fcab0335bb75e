// NeighbourIndex and fitLocalPlane against brute force and known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "process/local_plane.h"
#include "process/neighbour_index.h"

namespace parallax {
namespace {

std::vector<GridPoint> latticeWithDuplicates(std::size_t count, unsigned seed) {
  // Integer coordinates make many equal distances: ties at the K-th place are common.
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coord(0, 20);
  std::vector<GridPoint> points;
  for (std::size_t i = 0; i < count; ++i) {
    points.push_back({double(coord(rng)), double(coord(rng)), double(coord(rng)) * 0.5, i * 7 + 3});
  }
  points.push_back(points[5]);  // an exact duplicate, another id
  points.back().id = 1;
  points.push_back({500.0, 500.0, 500.0, 2});  // far from everything
  return points;
}

std::vector<Neighbour> bruteNearest(const std::vector<GridPoint>& points, double x, double y,
                                    double z, std::size_t k) {
  std::vector<Neighbour> all;
  for (std::size_t i = 0; i < points.size(); ++i) {
    all.push_back(
        {squaredDistance(x, y, z, points[i].x, points[i].y, points[i].z), 0, points[i].id});
  }
  std::sort(all.begin(), all.end());
  all.resize(std::min(k, all.size()));
  return all;
}

TEST(NeighbourIndex, NearestEqualsBruteForceWithTiesBrokenBySmallerId) {
  const std::vector<GridPoint> points = latticeWithDuplicates(3000, 1);
  {
    const NeighbourIndex grid(points);
    std::vector<Neighbour> found;
    for (std::size_t q = 0; q < points.size(); q += 37) {
      for (std::size_t k : {1u, 6u, 16u, 40u}) {
        grid.nearest(points[q].x, points[q].y, points[q].z, k, found);
        const std::vector<Neighbour> expected =
            bruteNearest(points, points[q].x, points[q].y, points[q].z, k);
        ASSERT_EQ(found.size(), expected.size());
        for (std::size_t i = 0; i < found.size(); ++i) {
          EXPECT_EQ(found[i].id, expected[i].id) << "query " << q << " k " << k;
          EXPECT_EQ(found[i].d2, expected[i].d2);
          EXPECT_EQ(grid.points()[found[i].at].id, found[i].id);
          EXPECT_EQ(grid.treePoints()[found[i].in_tree].id, found[i].id);
        }
      }
    }
    // A query far outside the grid, and the isolated point's own neighbours.
    grid.nearest(-300.0, 10.0, 10.0, 5, found);
    const std::vector<Neighbour> far = bruteNearest(points, -300.0, 10.0, 10.0, 5);
    ASSERT_EQ(found.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(found[i].id, far[i].id);
    grid.nearest(500.0, 500.0, 500.0, 3, found);
    const std::vector<Neighbour> lonely = bruteNearest(points, 500.0, 500.0, 500.0, 3);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(found[i].id, lonely[i].id);
  }
}

TEST(NeighbourIndex, AnEarlierAnswerInOutOnlyBoundsTheSearch) {
  // nearest() starts from the farthest of the k points `out` holds when they are this index's
  // (an earlier answer): queries asked in Morton order, each from the one before (ties at the
  // K-th place on the lattice and its duplicate), and answers of another index left in `out`
  // (their slots name other points here) give the brute force answers all the same.
  const std::vector<GridPoint> points = latticeWithDuplicates(3000, 1);
  std::vector<GridPoint> others = latticeWithDuplicates(2000, 9);
  for (GridPoint& p : others) p.id += 100000;  // other points, other ids, the same slots
  const NeighbourIndex grid(points), other(others);
  const std::vector<std::uint32_t> order = spatialOrder(points);
  std::vector<Neighbour> found, stale;
  for (std::size_t j = 0; j < order.size(); j += 11) {
    const GridPoint& q = points[order[j]];
    const std::vector<Neighbour> expected = bruteNearest(points, q.x, q.y, q.z, 16);
    grid.nearest(q.x, q.y, q.z, 16, found);  // from the answer of the query before
    other.nearest(q.x, q.y, q.z, 16, stale);
    grid.nearest(q.x, q.y, q.z, 16, stale);  // from another index's answer
    ASSERT_EQ(found.size(), expected.size());
    ASSERT_EQ(stale.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
      ASSERT_EQ(found[i].id, expected[i].id) << "query " << j;
      ASSERT_EQ(found[i].d2, expected[i].d2);
      ASSERT_EQ(stale[i].id, expected[i].id) << "query " << j;
      ASSERT_EQ(grid.points()[found[i].at].id, found[i].id);
    }
  }
}

TEST(NeighbourIndex, ClustersOfEveryDensityEqualBruteForce) {
  // Dense clusters a few millimetres wide beside sparse points a hundred metres apart, as a scan
  // is near and far from its station: the tree's boxes, split at Morton midpoints, are of every
  // size. Every answer equals the brute force one, and the plane read in tree order has the
  // same bits as the one read in the given order.
  std::mt19937 rng(11);
  std::normal_distribution<double> tight(0.0, 0.002);
  std::uniform_real_distribution<double> wide(-100.0, 100.0);
  std::vector<GridPoint> points;
  for (int cluster = 0; cluster < 6; ++cluster) {
    const double c[3] = {wide(rng), wide(rng), wide(rng) * 0.1};
    for (int i = 0; i < 1500; ++i) {
      points.push_back({c[0] + tight(rng), c[1] + tight(rng), c[2] + tight(rng), points.size()});
    }
  }
  for (int i = 0; i < 800; ++i) points.push_back({wide(rng), wide(rng), wide(rng), points.size()});
  std::shuffle(points.begin(), points.end(), rng);
  const NeighbourIndex grid(points);
  std::vector<Neighbour> found;
  for (std::size_t q = 0; q < points.size(); q += 29) {
    grid.nearest(points[q].x, points[q].y, points[q].z, 16, found);
    const std::vector<Neighbour> expected =
        bruteNearest(points, points[q].x, points[q].y, points[q].z, 16);
    ASSERT_EQ(found.size(), expected.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
      ASSERT_EQ(found[i].id, expected[i].id) << "query " << q;
      ASSERT_EQ(found[i].d2, expected[i].d2);
    }
    const LocalPlane given = fitLocalPlane(grid.points(), found);
    const LocalPlane in_tree = fitLocalPlane(grid, found);
    for (int a = 0; a < 3; ++a) ASSERT_EQ(given.normal[a], in_tree.normal[a]);
    ASSERT_EQ(given.curvature, in_tree.curvature);
  }
}

TEST(NeighbourIndex, MoreNeighboursAskedThanPointsGivesThemAll) {
  const std::vector<GridPoint> points = {{0, 0, 0, 4}, {1, 0, 0, 9}, {0, 2, 0, 1}};
  const NeighbourIndex grid(points);
  std::vector<Neighbour> found;
  grid.nearest(0, 0, 0, 10, found);
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].id, 4u);
  EXPECT_EQ(found[1].id, 9u);
  EXPECT_EQ(found[2].id, 1u);
}

TEST(NeighbourIndex, WithinRadiusEqualsBruteForceBoundaryIncluded) {
  const std::vector<GridPoint> points = latticeWithDuplicates(2000, 2);
  {
    const NeighbourIndex grid(points);
    std::vector<Neighbour> found;
    for (std::size_t q = 0; q < points.size(); q += 53) {
      const double radius = 2.0;  // integer lattice: points at exactly 2 exist
      grid.withinRadius(points[q].x, points[q].y, points[q].z, radius, found);
      std::vector<std::uint64_t> expected;
      for (const GridPoint& p : points) {
        if (squaredDistance(points[q].x, points[q].y, points[q].z, p.x, p.y, p.z) <= 4.0) {
          expected.push_back(p.id);
        }
      }
      std::vector<std::uint64_t> ids;
      for (const Neighbour& n : found) ids.push_back(n.id);
      std::sort(ids.begin(), ids.end());
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(ids, expected) << "query " << q;
    }
  }
}

TEST(NeighbourIndex, SpatialOrderIsMortonOrderOfTheCubeCorners) {
  // Corner (x, y, z) of the unit cube has Morton key x + 2y + 4z: listed in reverse, the order
  // gives them back ascending. A permutation whatever the points, duplicates included.
  std::vector<GridPoint> corners;
  for (int i = 7; i >= 0; --i) {
    corners.push_back({double(i & 1), double(i >> 1 & 1), double(i >> 2), std::uint64_t(i)});
  }
  const std::vector<std::uint32_t> order = spatialOrder(corners);
  ASSERT_EQ(order.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(corners[order[i]].id, i);

  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<GridPoint> points;
  for (std::uint64_t i = 0; i < 5000; ++i) points.push_back({u(random), u(random), 0.5, i});
  points.push_back(points[17]);
  std::vector<std::uint32_t> sorted = spatialOrder(points);
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) EXPECT_EQ(sorted[i], i);
}

TEST(LocalPlane, TiltedPlaneAndCurvature) {
  // Points of the plane z = 0.5 x - 0.25 y + 3 on a grid: normal (-0.5, 0.25, 1) normalised.
  std::vector<GridPoint> points;
  std::vector<Neighbour> all;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      points.push_back(
          {double(i), double(j), 0.5 * i - 0.25 * j + 3.0, std::uint64_t(points.size())});
      all.push_back({0.0, std::uint32_t(points.size() - 1), points.back().id});
    }
  }
  const LocalPlane plane = fitLocalPlane(points, all);
  ASSERT_TRUE(plane.valid);
  const double len = std::sqrt(0.25 + 0.0625 + 1.0);
  const double dot = (-0.5 * plane.normal[0] + 0.25 * plane.normal[1] + plane.normal[2]) / len;
  EXPECT_NEAR(std::abs(dot), 1.0, 1e-12);
  EXPECT_NEAR(plane.curvature, 0.0, 1e-12);
  EXPECT_NEAR(plane.centroid[0], 2.0, 1e-12);
  EXPECT_NEAR(plane.centroid[2], 0.5 * 2 - 0.25 * 2 + 3.0, 1e-12);
  // Points on a line have no plane.
  std::vector<GridPoint> line = {{0, 0, 0, 0}, {1, 1, 1, 1}, {2, 2, 2, 2}, {3, 3, 3, 3}};
  std::vector<Neighbour> line_all = {{0, 0, 0}, {0, 1, 1}, {0, 2, 2}, {0, 3, 3}};
  EXPECT_FALSE(fitLocalPlane(line, line_all).valid);
}

TEST(LocalPlane, EigenOfKnownMatrix) {
  const double m[3][3] = {{2, -1, 0}, {-1, 2, -1}, {0, -1, 2}};
  double values[3], vectors[3][3];
  symmetricEigen3(m, values, vectors);
  EXPECT_NEAR(values[0], 2.0 - std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(values[1], 2.0, 1e-14);
  EXPECT_NEAR(values[2], 2.0 + std::sqrt(2.0), 1e-14);
  // Smallest: (1, sqrt 2, 1) / 2 up to sign.
  EXPECT_NEAR(std::abs(vectors[0][0] + std::sqrt(2.0) * vectors[1][0] + vectors[2][0]) / 2.0, 1.0,
              1e-12);
}

TEST(LocalPlane, ClosedFormEqualsJacobi) {
  // Covariances R diag(l0, l1, l2) R^T of random rotations R, from flat (l0 a millionth of l1:
  // a noisy plane) to nearly isotropic, and the degenerate ones the closed form hands to Jacobi
  // (a line, a ball, a point, an axis-aligned plane): the same eigenvalues and, where the
  // smallest is single, the same vector up to sign.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::array<double, 3>> spectra = {
      {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0},    {1.0, 1.0, 1.0},    {0.0, 1.0, 1.0},
      {0.0, 2.0, 3.0}, {1e-6, 1.0, 2.0},   {1e-9, 0.5, 0.5},   {0.1, 0.2, 0.3},
      {0.9, 1.0, 1.1}, {3e-4, 2e-3, 1e-1}, {1e-12, 1e-5, 1e-5}};
  for (int round = 0; round < 400; ++round) {
    const std::array<double, 3> l = spectra[std::size_t(round) % spectra.size()];
    // A random rotation from a normalised quaternion (the first rounds: none).
    double w = 1, x = 0, y = 0, z = 0;
    if (round >= int(spectra.size())) {
      w = u(rng), x = u(rng), y = u(rng), z = u(rng);
      const double n = std::sqrt(w * w + x * x + y * y + z * z);
      w /= n, x /= n, y /= n, z /= n;
    }
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                            {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                            {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    double m[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        m[i][j] = 0.0;
        for (int k = 0; k < 3; ++k) m[i][j] += r[i][k] * l[std::size_t(k)] * r[j][k];
      }
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < i; ++j) m[i][j] = m[j][i];  // exactly symmetric
    }
    double jacobi_values[3], jacobi_vectors[3][3], values[3], vector[3];
    symmetricEigen3(m, jacobi_values, jacobi_vectors);
    smallestEigen3(m, values, vector);
    const double scale = l[2] + 1e-300;
    // lambda0 to rounding level; lambda1 and lambda2 to 1e-8 where they nearly meet (the
    // characteristic polynomial's double root), which only the validity test reads.
    for (int i = 0; i < 3; ++i) {
      const double tolerance = (i == 0 ? 1e-13 : 1e-7) * scale;
      EXPECT_NEAR(values[i], jacobi_values[i], tolerance) << "round " << round << " value " << i;
      EXPECT_NEAR(values[i], l[std::size_t(i)], tolerance) << "round " << round << " value " << i;
    }
    EXPECT_NEAR(vector[0] * vector[0] + vector[1] * vector[1] + vector[2] * vector[2], 1.0, 1e-14);
    if (l[1] - l[0] > 1e-6 * l[2]) {
      // The smallest's vector is R's first column, up to sign.
      const double dot = vector[0] * r[0][0] + vector[1] * r[1][0] + vector[2] * r[2][0];
      EXPECT_NEAR(std::abs(dot), 1.0, 1e-12) << "round " << round;
      const double jacobi_dot = vector[0] * jacobi_vectors[0][0] +
                                vector[1] * jacobi_vectors[1][0] + vector[2] * jacobi_vectors[2][0];
      EXPECT_NEAR(std::abs(jacobi_dot), 1.0, 1e-12) << "round " << round;
    }
  }
}

}  // namespace
}  // namespace parallax
