// ElevationGrid (elevation_grid.h): cells, filling, bilinear sampling and slope.
#include "terrain/elevation_grid.h"

#include <algorithm>
#include <cassert>

namespace parallax {

namespace {

// In double: a tiny cell makes more cells than any integer holds (an out-of-range conversion is
// undefined); the count is exact up to 2^53, far past any grid that is made.
double cellsAlong(double lo, double hi, double cell) {
  return std::floor((hi - lo) / cell) + 1.0;
}

}  // namespace

ElevationGrid::ElevationGrid(double x0, double y0, double cell, std::size_t nx, std::size_t ny)
    : x0_(x0), y0_(y0), cell_(cell), nx_(nx), ny_(ny), values_(nx * ny, kEmpty) {
  assert(cell > 0.0 && nx > 0 && ny > 0 && "a grid needs a positive cell and at least one cell");
}

double ElevationGrid::cellsCovering(double min_x, double min_y, double max_x, double max_y,
                                    double cell) {
  return cellsAlong(min_x, max_x, cell) * cellsAlong(min_y, max_y, cell);
}

ElevationGrid ElevationGrid::covering(double min_x, double min_y, double max_x, double max_y,
                                      double cell) {
  return ElevationGrid(min_x, min_y, cell, std::size_t(cellsAlong(min_x, max_x, cell)),
                       std::size_t(cellsAlong(min_y, max_y, cell)));
}

std::size_t ElevationGrid::column(double x) const {
  const double u = std::floor((x - x0_) / cell_);
  if (!(u > 0.0)) return 0;
  return std::min(nx_ - 1, std::size_t(std::min(u, double(nx_ - 1))));
}

std::size_t ElevationGrid::row(double y) const {
  const double v = std::floor((y - y0_) / cell_);
  if (!(v > 0.0)) return 0;
  return std::min(ny_ - 1, std::size_t(std::min(v, double(ny_ - 1))));
}

void ElevationGrid::fillEmpty() {
  // The ring being filled reads only cells filled before it: its values go to `next` first.
  std::vector<std::size_t> ring, next_ring;
  std::vector<std::uint8_t> filled(values_.size());
  for (std::size_t c = 0; c < values_.size(); ++c) filled[c] = !empty(values_[c]);
  auto neighboursOf = [&](std::size_t c, auto&& visit) {
    const std::size_t i = c % nx_, j = c / nx_;
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        if (di == 0 && dj == 0) continue;
        if ((i == 0 && di < 0) || (j == 0 && dj < 0) || (i + 1 == nx_ && di > 0) ||
            (j + 1 == ny_ && dj > 0)) {
          continue;
        }
        visit(std::size_t(std::ptrdiff_t(j) + dj) * nx_ + std::size_t(std::ptrdiff_t(i) + di));
      }
    }
  };
  // The first ring: empty cells with a filled neighbour, in cell order.
  std::vector<std::uint8_t> queued(values_.size());
  for (std::size_t c = 0; c < values_.size(); ++c) {
    if (filled[c]) continue;
    bool touches = false;
    neighboursOf(c, [&](std::size_t n) { touches = touches || filled[n]; });
    if (touches) {
      ring.push_back(c);
      queued[c] = 1;
    }
  }
  std::vector<double> fill;
  while (!ring.empty()) {
    std::sort(ring.begin(), ring.end());
    fill.assign(ring.size(), 0.0);
    for (std::size_t r = 0; r < ring.size(); ++r) {
      double sum = 0.0;
      int count = 0;
      neighboursOf(ring[r], [&](std::size_t n) {
        if (filled[n]) {
          sum += values_[n];
          ++count;
        }
      });
      fill[r] = sum / count;
    }
    next_ring.clear();
    for (std::size_t r = 0; r < ring.size(); ++r) {
      values_[ring[r]] = fill[r];
      filled[ring[r]] = 1;
    }
    for (std::size_t c : ring) {
      neighboursOf(c, [&](std::size_t n) {
        if (!filled[n] && !queued[n]) {
          queued[n] = 1;
          next_ring.push_back(n);
        }
      });
    }
    ring.swap(next_ring);
  }
}

double ElevationGrid::sample(double x, double y) const {
  // Positions in cell-centre units: centre i at u = i.
  auto axis = [](double u, std::size_t n, std::size_t& i0, double& t) {
    if (n == 1 || !(u > 0.0)) {
      i0 = 0;
      t = 0.0;
      return;
    }
    if (u >= double(n - 1)) {
      i0 = n - 2;
      t = 1.0;
      return;
    }
    i0 = std::size_t(u);
    t = u - double(i0);
  };
  std::size_t i0 = 0, j0 = 0;
  double tx = 0.0, ty = 0.0;
  axis((x - x0_) / cell_ - 0.5, nx_, i0, tx);
  axis((y - y0_) / cell_ - 0.5, ny_, j0, ty);
  const std::size_t i1 = nx_ == 1 ? 0 : i0 + 1, j1 = ny_ == 1 ? 0 : j0 + 1;
  const double bottom = at(i0, j0) * (1.0 - tx) + at(i1, j0) * tx;
  const double top = at(i0, j1) * (1.0 - tx) + at(i1, j1) * tx;
  return bottom * (1.0 - ty) + top * ty;
}

ElevationGrid ElevationGrid::slope() const {
  ElevationGrid out(x0_, y0_, cell_, nx_, ny_);
  auto derivative = [&](std::size_t i, std::size_t j, bool along_x) {
    const std::size_t n = along_x ? nx_ : ny_, k = along_x ? i : j;
    if (n == 1) return 0.0;
    const std::size_t lo = k == 0 ? 0 : k - 1, hi = k + 1 == n ? k : k + 1;
    const double a = along_x ? at(lo, j) : at(i, lo), b = along_x ? at(hi, j) : at(i, hi);
    return (b - a) / (double(hi - lo) * cell_);
  };
  for (std::size_t j = 0; j < ny_; ++j) {
    for (std::size_t i = 0; i < nx_; ++i) {
      const double gx = derivative(i, j, true), gy = derivative(i, j, false);
      out.at(i, j) = std::sqrt(gx * gx + gy * gy);
    }
  }
  return out;
}

}  // namespace parallax
