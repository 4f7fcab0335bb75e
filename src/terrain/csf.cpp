// CSF (csf.h): the falling cloth, its springs and the slope smoothing.
#include "terrain/csf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace parallax {

namespace {

constexpr double kDamping = 0.01;         // the paper's velocity damping
constexpr double kGravity = 0.2;          // the paper's acceleration
constexpr double kSettled = 0.005;        // the largest move of a step that ends the run
constexpr double kSmoothingHeight = 0.3;  // slope smoothing: a particle this close joins

}  // namespace

CsfCloth csfCloth(ElevationGrid minimum, const CsfParameters& p) {
  CsfCloth out;
  minimum.fillEmpty();
  if (minimum.cells() == 0 || ElevationGrid::empty(minimum.values()[0])) return out;
  // The surface upside down, and the cloth above its highest point.
  std::vector<double>& surface = minimum.values();
  for (double& v : surface) v = -v;
  const double top = *std::max_element(surface.begin(), surface.end()) + 1.0;
  const std::size_t nx = minimum.nx(), ny = minimum.ny(), n = surface.size();
  std::vector<double> z(n, top), previous(n, top);
  std::vector<std::uint8_t> movable(n, 1);
  const double fall = kGravity * p.time_step * p.time_step;

  auto spring = [&](std::size_t a, std::size_t b) {
    const double d = z[b] - z[a];
    if (movable[a] && movable[b]) {
      z[a] += d / 2.0;
      z[b] -= d / 2.0;
    } else if (movable[a]) {
      z[a] += d / 2.0;
    } else if (movable[b]) {
      z[b] -= d / 2.0;
    }
  };
  for (out.steps = 0; out.steps < p.iterations;) {
    ++out.steps;
    double moved = 0.0;
    for (std::size_t c = 0; c < n; ++c) {
      if (!movable[c]) continue;
      const double next = z[c] + (z[c] - previous[c]) * (1.0 - kDamping) - fall;
      previous[c] = z[c];
      z[c] = next;
    }
    for (int round = 0; round < p.rigidness; ++round) {
      for (std::size_t j = 0; j < ny; ++j) {
        for (std::size_t i = 0; i < nx; ++i) {
          const std::size_t c = j * nx + i;
          if (i + 1 < nx) spring(c, c + 1);
          if (j + 1 < ny) spring(c, c + nx);
        }
      }
    }
    for (std::size_t c = 0; c < n; ++c) {
      if (!movable[c]) continue;
      if (z[c] <= surface[c]) {
        z[c] = surface[c];
        movable[c] = 0;
      }
      moved = std::max(moved, std::abs(z[c] - previous[c]));
    }
    if (moved < kSettled) break;
  }

  if (p.slope_smoothing) {
    std::vector<std::size_t> ring;
    auto joins = [&](std::size_t c) {
      return movable[c] && std::abs(z[c] - surface[c]) < kSmoothingHeight;
    };
    auto visit = [&](std::size_t c, auto&& f) {
      const std::size_t i = c % nx, j = c / nx;
      if (i > 0) f(c - 1);
      if (i + 1 < nx) f(c + 1);
      if (j > 0) f(c - nx);
      if (j + 1 < ny) f(c + nx);
    };
    for (std::size_t c = 0; c < n; ++c) {
      if (movable[c]) continue;
      visit(c, [&](std::size_t m) {
        if (joins(m)) {
          z[m] = surface[m];
          movable[m] = 0;
          ring.push_back(m);
        }
      });
    }
    while (!ring.empty()) {
      std::vector<std::size_t> next;
      for (std::size_t c : ring) {
        visit(c, [&](std::size_t m) {
          if (joins(m)) {
            z[m] = surface[m];
            movable[m] = 0;
            next.push_back(m);
          }
        });
      }
      ring.swap(next);
    }
  }
  out.height = ElevationGrid(minimum.x0(), minimum.y0(), minimum.cell(), nx, ny);
  out.height.values() = std::move(z);
  return out;
}

bool csfIsGround(const CsfCloth& cloth, const CsfParameters& p, double x, double y, double z) {
  if (cloth.height.cells() == 0) return false;
  return std::abs(-z - cloth.height.sample(x, y)) < p.class_threshold;
}

}  // namespace parallax
