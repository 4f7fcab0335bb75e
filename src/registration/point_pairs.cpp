// rigidTransformFromPairs (point_pairs.h): Horn's quaternion solution.
#include "registration/point_pairs.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace parallax {

namespace {

// Eigenvalues and eigenvectors of a symmetric N x N matrix by cyclic Jacobi rotations (N is 3 or
// 4 here: a handful of sweeps reach double precision). `a` is destroyed: its diagonal ends as the
// eigenvalues; column k of `v` is the eigenvector of a[k][k].
template <std::size_t N>
void jacobiEigenOfPairs(std::array<std::array<double, N>, N>& a,
                        std::array<std::array<double, N>, N>& v) {
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j < N; ++j) v[i][j] = i == j ? 1.0 : 0.0;
  }
  for (int sweep = 0; sweep < 64; ++sweep) {
    double off = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < N; ++i) {
      scale += a[i][i] * a[i][i];
      for (std::size_t j = i + 1; j < N; ++j) off += a[i][j] * a[i][j];
    }
    if (off <= 1e-30 * scale || off == 0.0) return;
    for (std::size_t p = 0; p < N; ++p) {
      for (std::size_t q = p + 1; q < N; ++q) {
        if (a[p][q] == 0.0) continue;
        // The rotation that zeroes a[p][q] (Golub and Van Loan, the symmetric Schur step).
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::hypot(theta, 1.0));
        const double c = 1.0 / std::hypot(t, 1.0), s = t * c;
        for (std::size_t k = 0; k < N; ++k) {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (std::size_t k = 0; k < N; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (std::size_t k = 0; k < N; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
}

std::array<double, 3> centroidOfPairs(std::span<const std::array<double, 3>> points) {
  std::array<double, 3> c{0, 0, 0};
  for (const auto& p : points) {
    for (int a = 0; a < 3; ++a) c[a] += p[a];
  }
  for (int a = 0; a < 3; ++a) c[a] /= double(points.size());
  return c;
}

}  // namespace

PairFit rigidTransformFromPairs(std::span<const std::array<double, 3>> source,
                                std::span<const std::array<double, 3>> target) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("point pairs: " + std::to_string(source.size()) +
                                " source points but " + std::to_string(target.size()) +
                                " target points; each source point needs its partner");
  }
  if (source.size() < 3) {
    throw std::invalid_argument("point pairs: " + std::to_string(source.size()) +
                                " pairs; three are needed to fix a rigid transform");
  }
  const std::array<double, 3> cs = centroidOfPairs(source), ct = centroidOfPairs(target);
  // S[i][j] = sum a_i b_j over the centred pairs (a source, b target); C the source's spread.
  std::array<std::array<double, 3>, 3> s{}, spread{};
  for (std::size_t k = 0; k < source.size(); ++k) {
    double a[3], b[3];
    for (int i = 0; i < 3; ++i) a[i] = source[k][i] - cs[i], b[i] = target[k][i] - ct[i];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        s[i][j] += a[i] * b[j];
        spread[i][j] += a[i] * a[j];
      }
    }
  }
  // Points on a line: the spread has one nonzero eigenvalue, the rotation about the line is free.
  std::array<std::array<double, 3>, 3> spread_vectors{};
  jacobiEigenOfPairs<3>(spread, spread_vectors);
  double e[3] = {spread[0][0], spread[1][1], spread[2][2]};
  std::sort(e, e + 3);
  if (!(e[1] > 1e-12 * e[2])) {
    throw std::invalid_argument(
        "point pairs: the source points lie on one line (or on one point); pick a third point "
        "away from the line through the others");
  }
  // Horn's N (the quaternion (w, x, y, z) maximizing sum b . R a is its top eigenvector).
  const double sxx = s[0][0], sxy = s[0][1], sxz = s[0][2], syx = s[1][0], syy = s[1][1],
               syz = s[1][2], szx = s[2][0], szy = s[2][1], szz = s[2][2];
  std::array<std::array<double, 4>, 4> n{{
      {sxx + syy + szz, syz - szy, szx - sxz, sxy - syx},
      {syz - szy, sxx - syy - szz, sxy + syx, szx + sxz},
      {szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy},
      {sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz},
  }};
  std::array<std::array<double, 4>, 4> vectors{};
  jacobiEigenOfPairs<4>(n, vectors);
  std::size_t top = 0;
  for (std::size_t k = 1; k < 4; ++k) {
    if (n[k][k] > n[top][top]) top = k;
  }
  double w = vectors[0][top], x = vectors[1][top], y = vectors[2][top], z = vectors[3][top];
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  w /= norm, x /= norm, y /= norm, z /= norm;
  PairFit fit;
  auto& m = fit.transform.m;
  m[0] = {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y), 0};
  m[1] = {2 * (y * x + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x), 0};
  m[2] = {2 * (z * x - w * y), 2 * (z * y + w * x), w * w - x * x - y * y + z * z, 0};
  // t = ct - R cs, so that the centroids match.
  for (int i = 0; i < 3; ++i) {
    m[i][3] = ct[i] - (m[i][0] * cs[0] + m[i][1] * cs[1] + m[i][2] * cs[2]);
  }
  double sum = 0.0;
  for (std::size_t k = 0; k < source.size(); ++k) {
    // Centred, so that large coordinates do not cancel: R (p - cs) + ct - q.
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double moved = m[i][0] * (source[k][0] - cs[0]) + m[i][1] * (source[k][1] - cs[1]) +
                           m[i][2] * (source[k][2] - cs[2]) + ct[i];
      d2 += (moved - target[k][i]) * (moved - target[k][i]);
    }
    sum += d2;
  }
  fit.rms = std::sqrt(sum / double(source.size()));
  return fit;
}

}  // namespace parallax
