// The cell grid the samplers share: a node's cube cut into at most 128^3 cells no smaller than
// the spacing, with per-thread storage reused from node to node (a stamp per cell says whether
// the cell was touched for the current node, so nothing is cleared between nodes).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/bounds.h"

namespace parallax::sampler_detail {

class CellGrid {
 public:
  static constexpr int kMaxCells = 128;

  // Prepares the grid for one node; every cell reads as empty afterwards.
  void reset(const Bounds3& box, double spacing) {
    const double edge = box.max[0] - box.min[0];
    // edge / spacing is 128 up to rounding for the default spacing: the tolerance keeps it from
    // flooring to 127 (a cell is then shorter than the spacing by at most 1e-12 of it).
    cells_ = int(std::clamp(std::floor(edge / spacing * (1.0 + 1e-12)), 1.0, double(kMaxCells)));
    inverse_cell_ = double(cells_) / edge;
    const std::size_t total = std::size_t(cells_) * cells_ * cells_;
    if (cells_by_index_.size() < total) {
      cells_by_index_.assign(total, Cell{});
      generation_ = 0;
    }
    if (++generation_ == 0) {  // wrapped: stale stamps could read as current
      std::fill(cells_by_index_.begin(), cells_by_index_.end(), Cell{});
      generation_ = 1;
    }
  }

  int cells() const { return cells_; }
  double cellSize() const { return 1.0 / inverse_cell_; }
  // Cell coordinate of a local coordinate (world minus the box minimum), clamped into the grid.
  int cellOf(double local) const {
    const int c = int(local * inverse_cell_);
    return std::clamp(c, 0, cells_ - 1);
  }
  std::size_t index(int x, int y, int z) const {
    return (std::size_t(x) * cells_ + std::size_t(y)) * cells_ + std::size_t(z);
  }
  // Head of the cell's list, -1 when empty.
  std::int32_t head(std::size_t cell) const {
    const Cell& c = cells_by_index_[cell];
    return c.stamp == generation_ ? c.head : -1;
  }
  void setHead(std::size_t cell, std::int32_t value) {
    cells_by_index_[cell] = {generation_, value};
  }

 private:
  int cells_ = 1;
  double inverse_cell_ = 1.0;
  std::uint32_t generation_ = 0;
  // Stamp and head side by side: one cache line fetch per cell looked at.
  struct Cell {
    std::uint32_t stamp = 0;
    std::int32_t head = -1;
  };
  std::vector<Cell> cells_by_index_;
};

}  // namespace parallax::sampler_detail
