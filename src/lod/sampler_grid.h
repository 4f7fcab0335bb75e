// The cell grid the samplers share: a node's cube cut into at most 128^3 cells no smaller than
// the spacing, with per-thread storage reused from node to node. A bit per cell says whether it
// holds anything for the current node: the 256 KB bitmap stays in cache, so the many empty
// cells around a surface are passed over without touching the 8 MB of list heads, and only the
// bits' words that were set are cleared for the next node.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/bounds.h"

namespace parallax::sampler_detail {

// Bit i of a 7-bit cell coordinate moved to bit 3i (Morton order of the cells).
constexpr std::array<std::uint32_t, 128> spreadTable() {
  std::array<std::uint32_t, 128> table{};
  for (std::uint32_t v = 0; v < 128; ++v) {
    for (int bit = 0; bit < 7; ++bit) table[v] |= ((v >> bit) & 1u) << (3 * bit);
  }
  return table;
}
inline constexpr std::array<std::uint32_t, 128> kSpread = spreadTable();

class CellGrid {
 public:
  static constexpr int kMaxCells = 128;
  static_assert(kMaxCells == int(kSpread.size()));

  // Prepares the grid for one node; every cell reads as empty afterwards.
  void reset(const Bounds3& box, double spacing) {
    const double edge = box.max[0] - box.min[0];
    // edge / spacing is 128 up to rounding for the default spacing: the tolerance keeps it from
    // flooring to 127 (a cell is then shorter than the spacing by at most 1e-12 of it).
    cells_ = int(std::clamp(std::floor(edge / spacing * (1.0 + 1e-12)), 1.0, double(kMaxCells)));
    inverse_cell_ = double(cells_) / edge;
    // Morton indices of a grid with a side that is not a power of two reach up to the next one.
    std::size_t side = 1;
    while (side < std::size_t(cells_)) side *= 2;
    const std::size_t total = side * side * side;
    if (heads_.size() < total) {
      heads_.resize(total);
      occupied_.assign((total + 63) / 64, 0);
      touched_.clear();
    }
    for (const std::size_t word : touched_) occupied_[word] = 0;
    touched_.clear();
  }

  int cells() const { return cells_; }
  double cellSize() const { return 1.0 / inverse_cell_; }
  // Cell coordinate of a local coordinate (world minus the box minimum), clamped into the grid.
  int cellOf(double local) const {
    const int c = int(local * inverse_cell_);
    return std::clamp(c, 0, cells_ - 1);
  }
  // Cells are stored in Morton order: the candidates come in Morton order too, so consecutive
  // candidates and their neighbours touch nearby memory (in x-y-z order the 16 MB grid of a
  // 128^3 node cost a cache and TLB miss per look).
  std::size_t index(int x, int y, int z) const {
    return kSpread[std::size_t(x)] << 2 | kSpread[std::size_t(y)] << 1 | kSpread[std::size_t(z)];
  }
  // Head of the cell's list, -1 when empty.
  std::int32_t head(std::size_t cell) const {
    return (occupied_[cell >> 6] >> (cell & 63) & 1) != 0 ? heads_[cell] : -1;
  }
  void setHead(std::size_t cell, std::int32_t value) {
    std::uint64_t& word = occupied_[cell >> 6];
    if (word == 0) touched_.push_back(cell >> 6);
    word |= std::uint64_t(1) << (cell & 63);
    heads_[cell] = value;
  }

 private:
  int cells_ = 1;
  double inverse_cell_ = 1.0;
  std::vector<std::int32_t> heads_;      // valid where the cell's bit is set
  std::vector<std::uint64_t> occupied_;  // a bit per cell
  std::vector<std::size_t> touched_;     // words of occupied_ set since the last reset
};

}  // namespace parallax::sampler_detail
