// NeighbourGrid (neighbour_grid.h): ring search over a hashed uniform grid.
#include "process/neighbour_grid.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace parallax {

namespace {

constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
constexpr std::int64_t kMaxCells = (std::int64_t(1) << 21) - 1;  // 21 bits a coordinate

std::uint64_t hashKey(std::uint64_t key) {
  key ^= key >> 31;
  key *= 0x9E3779B97F4A7C15ull;
  return key ^ (key >> 29);
}

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

}  // namespace

double NeighbourGrid::cellForDensity(std::span<const GridPoint> points, double per_cell) {
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

NeighbourGrid::NeighbourGrid(std::vector<GridPoint> points, double cell)
    : points_(std::move(points)) {
  assert(cell > 0.0 && "NeighbourGrid: the cell edge must be positive");
  assert(points_.size() < std::numeric_limits<std::uint32_t>::max() &&
         "NeighbourGrid: at most 2^32 - 1 points");
  const Box box = boxOf(points_);
  double largest = 0.0;
  for (int a = 0; a < 3; ++a) largest = std::max(largest, box.max[a] - box.min[a]);
  cell_ = std::max(cell, largest / double(kMaxCells - 1));
  for (int a = 0; a < 3; ++a) {
    origin_[a] = box.min[a];
    extent_[a] = std::int64_t((box.max[a] - box.min[a]) / cell_) + 1;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const GridPoint& p = points_[i];
    keyed[i] = {keyOf(cellCoord(0, p.x), cellCoord(1, p.y), cellCoord(2, p.z)), std::uint32_t(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<GridPoint> sorted(points_.size());
  std::size_t cells = 0;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    sorted[i] = points_[keyed[i].second];
    if (i == 0 || keyed[i].first != keyed[i - 1].first) ++cells;
  }
  points_ = std::move(sorted);
  table_.assign(std::bit_ceil(std::max<std::size_t>(2 * cells, 2)), Cell{kEmpty, 0, 0});
  mask_ = table_.size() - 1;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i + 1;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    std::uint64_t slot = hashKey(keyed[i].first) & mask_;
    while (table_[slot].key != kEmpty) slot = (slot + 1) & mask_;
    table_[slot] = {keyed[i].first, std::uint32_t(i), std::uint32_t(j)};
    i = j;
  }
}

std::int64_t NeighbourGrid::cellCoord(int axis, double v) const {
  return std::int64_t(std::floor((v - origin_[axis]) / cell_));
}

std::uint64_t NeighbourGrid::keyOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  return (std::uint64_t(ix) << 42) | (std::uint64_t(iy) << 21) | std::uint64_t(iz);
}

const NeighbourGrid::Cell* NeighbourGrid::find(std::int64_t ix, std::int64_t iy,
                                               std::int64_t iz) const {
  if (ix < 0 || iy < 0 || iz < 0 || ix >= extent_[0] || iy >= extent_[1] || iz >= extent_[2]) {
    return nullptr;
  }
  const std::uint64_t key = keyOf(ix, iy, iz);
  for (std::uint64_t slot = hashKey(key) & mask_;; slot = (slot + 1) & mask_) {
    const Cell& c = table_[slot];
    if (c.key == key) return &c;
    if (c.key == kEmpty) return nullptr;
  }
}

void NeighbourGrid::nearest(double x, double y, double z, std::size_t k,
                            std::vector<Neighbour>& out) const {
  out.clear();
  if (k == 0 || points_.empty()) return;
  const double q[3] = {x, y, z};
  std::int64_t qc[3];
  for (int a = 0; a < 3; ++a) {
    qc[a] = std::clamp<std::int64_t>(cellCoord(a, q[a]), -1, extent_[a]);
  }
  auto offer = [&](const Cell& c) {
    for (std::uint32_t i = c.begin; i < c.end; ++i) {
      const GridPoint& p = points_[i];
      const Neighbour n{squaredDistance(x, y, z, p.x, p.y, p.z), i, p.id};
      if (out.size() < k) {
        out.push_back(n);
        std::push_heap(out.begin(), out.end());
      } else if (n < out.front()) {
        std::pop_heap(out.begin(), out.end());
        out.back() = n;
        std::push_heap(out.begin(), out.end());
      }
    }
  };
  const std::size_t occupied = (mask_ + 1) / 2;
  for (std::int64_t r = 0;; ++r) {
    // Beyond a few rings on a sparse grid, walking every occupied cell costs less than the rings.
    if (r > 2 &&
        double(2 * r + 1) * double(2 * r + 1) * double(2 * r + 1) > 8.0 * double(occupied)) {
      for (const Cell& c : table_) {
        if (c.key == kEmpty) continue;
        if (out.size() == k) {
          const std::int64_t cx = std::int64_t(c.key >> 42),
                             cy = std::int64_t((c.key >> 21) & kMaxCells),
                             cz = std::int64_t(c.key & kMaxCells);
          const std::int64_t cc[3] = {cx, cy, cz};
          double box_d2 = 0.0;
          for (int a = 0; a < 3; ++a) {
            const double lo = origin_[a] + double(cc[a]) * cell_, hi = lo + cell_;
            const double d = q[a] < lo ? lo - q[a] : (q[a] > hi ? q[a] - hi : 0.0);
            box_d2 += d * d;
          }
          if (box_d2 > out.front().d2 * 1.000001 + 1e-300) continue;
        }
        // Cells already offered by the rings are skipped: they are within ring r - 1.
        const std::int64_t cx = std::int64_t(c.key >> 42),
                           cy = std::int64_t((c.key >> 21) & kMaxCells),
                           cz = std::int64_t(c.key & kMaxCells);
        if (std::abs(cx - qc[0]) < r && std::abs(cy - qc[1]) < r && std::abs(cz - qc[2]) < r)
          continue;
        offer(c);
      }
      break;
    }
    bool beyond_all = true;
    for (int a = 0; a < 3; ++a) {
      if (qc[a] - r > 0 || qc[a] + r < extent_[a] - 1) beyond_all = false;
    }
    for (std::int64_t dx = -r; dx <= r; ++dx) {
      for (std::int64_t dy = -r; dy <= r; ++dy) {
        const bool inner = std::abs(dx) < r && std::abs(dy) < r;
        for (std::int64_t dz = -r; dz <= r; dz += (inner ? 2 * r : 1)) {
          if (const Cell* c = find(qc[0] + dx, qc[1] + dy, qc[2] + dz)) offer(*c);
          if (r == 0) break;
        }
      }
    }
    if (beyond_all) break;
    if (out.size() == k) {
      double covered = std::numeric_limits<double>::max();
      for (int a = 0; a < 3; ++a) {
        const double lo = origin_[a] + double(qc[a] - r) * cell_;
        const double hi = origin_[a] + double(qc[a] + r + 1) * cell_;
        covered = std::min({covered, q[a] - lo, hi - q[a]});
      }
      // A hair of margin: the faces are computed, not exact.
      if (covered > 0.0 && out.front().d2 < covered * covered * (1.0 - 1e-9)) break;
    }
  }
  std::sort(out.begin(), out.end());
}

void NeighbourGrid::withinRadius(double x, double y, double z, double radius,
                                 std::vector<Neighbour>& out) const {
  out.clear();
  if (points_.empty() || !(radius >= 0.0)) return;
  const double r2 = radius * radius;
  const double q[3] = {x, y, z};
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max<std::int64_t>(0, cellCoord(a, q[a] - radius) - 1);
    hi[a] = std::min<std::int64_t>(extent_[a] - 1, cellCoord(a, q[a] + radius) + 1);
  }
  const double span =
      double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
  auto offer = [&](const Cell& c) {
    for (std::uint32_t i = c.begin; i < c.end; ++i) {
      const GridPoint& p = points_[i];
      const double d2 = squaredDistance(x, y, z, p.x, p.y, p.z);
      if (d2 <= r2) out.push_back({d2, i, p.id});
    }
  };
  if (span > double(table_.size())) {
    for (const Cell& c : table_) {
      if (c.key != kEmpty) offer(c);
    }
  } else {
    for (std::int64_t ix = lo[0]; ix <= hi[0]; ++ix) {
      for (std::int64_t iy = lo[1]; iy <= hi[1]; ++iy) {
        for (std::int64_t iz = lo[2]; iz <= hi[2]; ++iz) {
          if (const Cell* c = find(ix, iy, iz)) offer(*c);
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
}

}  // namespace parallax
