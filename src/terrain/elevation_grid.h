// A regular grid of elevations over the xy plane: the rasters the ground filters work on
// (a minimum surface built by streaming the points through it, then filled, opened and sampled).
//
// Cell (i, j) covers [x0 + i c, x0 + (i + 1) c) x [y0 + j c, y0 + (j + 1) c); its value stands
// for its centre. An empty cell holds NaN. Values are double: a grid costs 8 bytes a cell, and
// every operation is a fixed sequence over the cells, so the same points give the same bits
// whatever order they arrive in.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace parallax {

class ElevationGrid {
 public:
  static constexpr double kEmpty = std::numeric_limits<double>::quiet_NaN();

  ElevationGrid() = default;
  // A grid of `nx` x `ny` cells of edge `cell` from (x0, y0), every cell empty.
  ElevationGrid(double x0, double y0, double cell, std::size_t nx, std::size_t ny);
  // The grid covering [min_x, max_x] x [min_y, max_y] with cells of edge `cell` from the minimum
  // corner (the maximum falls in the last cell).
  static ElevationGrid covering(double min_x, double min_y, double max_x, double max_y,
                                double cell);
  // Cells the grid covering that box would have (to check a budget before allocating it), as a
  // double: a tiny cell gives more than 2^64.
  static double cellsCovering(double min_x, double min_y, double max_x, double max_y, double cell);

  std::size_t nx() const { return nx_; }
  std::size_t ny() const { return ny_; }
  std::size_t cells() const { return values_.size(); }
  double cell() const { return cell_; }
  double x0() const { return x0_; }
  double y0() const { return y0_; }

  double& at(std::size_t i, std::size_t j) { return values_[j * nx_ + i]; }
  double at(std::size_t i, std::size_t j) const { return values_[j * nx_ + i]; }
  static bool empty(double value) { return std::isnan(value); }
  std::vector<double>& values() { return values_; }
  const std::vector<double>& values() const { return values_; }

  // The cell holding (x, y), clamped to the grid (points on the maximum edge fall in the last).
  std::size_t column(double x) const;
  std::size_t row(double y) const;

  // Lowers cell (x, y) to z when z is lower or the cell is empty.
  void addMinimum(double x, double y, double z) {
    double& v = at(column(x), row(y));
    if (empty(v) || z < v) v = z;
  }

  // Fills every empty cell from its filled neighbours, ring by ring outwards: a cell next to
  // filled cells takes the mean of its filled 8-neighbours, then those filled that way fill the
  // next ring. A grid without a filled cell stays empty. (Pingel et al. 2013 inpaint with a
  // spline; the rings are cheaper and keep the grid's bits independent of the order of points.)
  void fillEmpty();

  // The value at (x, y), bilinear between the centres of the four nearest cells (clamped at the
  // grid's edges). The grid must be filled.
  double sample(double x, double y) const;

  // The slope (rise over run, |gradient|) of every cell by central differences (one-sided at the
  // edges); a one-cell axis has no slope along it. The grid must be filled.
  ElevationGrid slope() const;

 private:
  double x0_ = 0.0, y0_ = 0.0, cell_ = 1.0;
  std::size_t nx_ = 0, ny_ = 0;
  std::vector<double> values_;
};

}  // namespace parallax
