// fitLocalPlane and the 3x3 eigen solvers (local_plane.h).
#include "process/local_plane.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace parallax {

void symmetricEigen3(const double matrix[3][3], double values[3], double vectors[3][3]) {
  double a[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      a[i][j] = matrix[i][j];
      vectors[i][j] = i == j ? 1.0 : 0.0;
    }
  }
  // Jacobi converges quadratically: a handful of sweeps reach rounding level. Chosen over the
  // closed form (trigonometric roots), which loses the smallest eigenvalue's vector on nearly
  // flat neighbourhoods, exactly the case normals are about.
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= diag * 1e-32 || off == 0.0) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = vectors[k][p], vkq = vectors[k][q];
          vectors[k][p] = c * vkp - s * vkq;
          vectors[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3,
            [&](int i, int j) { return a[i][i] < a[j][j] || (a[i][i] == a[j][j] && i < j); });
  double sorted_vectors[3][3];
  for (int i = 0; i < 3; ++i) {
    values[i] = a[order[i]][order[i]];
    for (int k = 0; k < 3; ++k) sorted_vectors[k][i] = vectors[k][order[i]];
  }
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) vectors[i][k] = sorted_vectors[i][k];
  }
}

namespace {

// `position(n)`: the neighbour's point.
template <class Position>
LocalPlane fitPlane(std::span<const Neighbour> neighbours, Position&& position) {
  LocalPlane plane;
  if (neighbours.size() < 3) return plane;
  // Centred on the first neighbour before summing: world coordinates of 500 000 m would lose the
  // millimetres in the squares.
  const GridPoint& base = position(neighbours[0]);
  double mean[3] = {0, 0, 0};
  for (const Neighbour& n : neighbours) {
    const GridPoint& p = position(n);
    mean[0] += p.x - base.x;
    mean[1] += p.y - base.y;
    mean[2] += p.z - base.z;
  }
  const double count = double(neighbours.size());
  for (double& m : mean) m /= count;
  double cov[3][3] = {};
  for (const Neighbour& n : neighbours) {
    const GridPoint& p = position(n);
    const double d[3] = {p.x - base.x - mean[0], p.y - base.y - mean[1], p.z - base.z - mean[2]};
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j) cov[i][j] += d[i] * d[j];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      cov[i][j] /= count;
      cov[j][i] = cov[i][j];
    }
  }
  double values[3];
  smallestEigen3(cov, values, plane.normal);
  plane.centroid[0] = base.x + mean[0];
  plane.centroid[1] = base.y + mean[1];
  plane.centroid[2] = base.z + mean[2];
  const double sum = values[0] + values[1] + values[2];
  plane.curvature = sum > 0.0 ? std::max(0.0, values[0]) / sum : 0.0;
  // On a line (or a point) the plane is undetermined: the two smallest eigenvalues are equal.
  plane.valid = values[1] > sum * 1e-12;
  return plane;
}

}  // namespace

void smallestEigen3(const double m[3][3], double values[3], double vector[3]) {
  auto jacobi = [&] {
    double vectors[3][3];
    symmetricEigen3(m, values, vectors);
    for (int k = 0; k < 3; ++k) vector[k] = vectors[k][0];
  };
  // B = (A - q I) / p has eigenvalues 2 cos(phi + 2 pi j / 3), phi = acos(det(B) / 2) / 3.
  const double q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
  const double b00 = m[0][0] - q, b11 = m[1][1] - q, b22 = m[2][2] - q;
  const double b01 = m[0][1], b02 = m[0][2], b12 = m[1][2];
  const double p2 =
      (b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * (b01 * b01 + b02 * b02 + b12 * b12)) / 6.0;
  const double p = std::sqrt(p2);
  if (!(p > 0.0) || !std::isfinite(p)) return jacobi();  // a multiple of I (or not finite)
  const double det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  const double half = std::clamp(det / (2.0 * p2 * p), -1.0, 1.0);
  const double phi = std::acos(half) / 3.0;
  constexpr double kThird = 2.0943951023931954923;  // 2 pi / 3
  values[2] = q + 2.0 * p * std::cos(phi);
  values[0] = q + 2.0 * p * std::cos(phi + kThird);
  values[1] = 3.0 * q - values[0] - values[2];
  if (values[1] - values[0] <= 1e-6 * (std::abs(q) + p)) return jacobi();
  // A - lambda0 I has rank 2: its null vector is the cross product of two independent rows,
  // the largest of the three products the best conditioned.
  const double r[3][3] = {{m[0][0] - values[0], m[0][1], m[0][2]},
                          {m[0][1], m[1][1] - values[0], m[1][2]},
                          {m[0][2], m[1][2], m[2][2] - values[0]}};
  double best[3] = {0, 0, 0}, best_length2 = -1.0;
  for (int i = 0; i < 2; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double c[3] = {r[i][1] * r[j][2] - r[i][2] * r[j][1],
                           r[i][2] * r[j][0] - r[i][0] * r[j][2],
                           r[i][0] * r[j][1] - r[i][1] * r[j][0]};
      const double length2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
      if (length2 > best_length2) {
        best_length2 = length2;
        for (int k = 0; k < 3; ++k) best[k] = c[k];
      }
    }
  }
  if (!(best_length2 > 0.0)) return jacobi();
  const double length = std::sqrt(best_length2);
  for (int k = 0; k < 3; ++k) vector[k] = best[k] / length;
  // The roots lose half their digits where two of them nearly meet (acos near +-1: a disc-shaped
  // neighbourhood has lambda1 = lambda2), and lambda0 with them; its Rayleigh quotient v^T A v
  // errs by the square of the vector's error, back to rounding level (the curvature's numerator).
  double rayleigh = 0.0;
  for (int i = 0; i < 3; ++i) {
    rayleigh += vector[i] * (m[i][0] * vector[0] + m[i][1] * vector[1] + m[i][2] * vector[2]);
  }
  values[0] = rayleigh;
}

LocalPlane fitLocalPlane(std::span<const GridPoint> points, std::span<const Neighbour> neighbours) {
  return fitPlane(neighbours, [&](const Neighbour& n) -> const GridPoint& { return points[n.at]; });
}

LocalPlane fitLocalPlane(const NeighbourIndex& index, std::span<const Neighbour> neighbours) {
  const std::span<const GridPoint> points = index.treePoints();
  return fitPlane(neighbours,
                  [&](const Neighbour& n) -> const GridPoint& { return points[n.in_tree]; });
}

}  // namespace parallax
