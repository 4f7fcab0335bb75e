// Analytic piles on a sloped base, written as a text cloud (x y z a line), and the base as a
// raster, of the volume tests (test_volume.cpp: `computeVolume` against closed forms;
// tests/render/test_viewer_panels.cpp: the viewer's Volume tool).
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <sstream>

#include "raster/raster_grid.h"
#include "raster/raster_image.h"
#include "support/temp_dir.h"

namespace parallax::test {

using Height = std::function<double(double, double)>;

inline double slopedBase(double x, double y) {
  return 0.1 * x + 0.05 * y + 20.0;
}

inline double cone(double x, double y) {  // radius 8, height 4, at (10, 10)
  const double r = std::hypot(x - 10, y - 10);
  return r < 8 ? 4 * (1 - r / 8) : 0;
}
// Points on z = base + pile over [-1, 21]^2: `per_side` x `per_side` a cell of `resolution`,
// symmetric about the cell's centre (one point: the centre).
inline std::filesystem::path writeCloud(const TempDir& dir, const Height& base, const Height& pile,
                                        double resolution, int per_side) {
  std::ostringstream text;
  text.precision(6);
  text << std::fixed;
  const int cells = int(std::lround(22 / resolution));
  for (int row = 0; row < cells; ++row) {
    for (int column = 0; column < cells; ++column) {
      for (int i = 0; i < per_side; ++i) {
        for (int j = 0; j < per_side; ++j) {
          const double x = -1 + (column + (i + 0.5) / per_side) * resolution;
          const double y = -1 + (row + (j + 0.5) / per_side) * resolution;
          text << x << ' ' << y << ' ' << base(x, y) + pile(x, y) << '\n';
        }
      }
    }
  }
  return dir.write("cloud.xyz", text.str());
}

// The sloped base as a raster of cells of 0.5 over [left, right] x [bottom, top] (their values
// the plane at their centres, in float), aligned with a volume's 0.5 grid: each counted cell's
// base is the plane at its centre.
inline RasterImage slopedBaseRaster(double left, double bottom, double right, double top) {
  RasterImage base;
  base.grid = boundedGrid(left, bottom, right, top, 0.5);
  base.values.resize(base.grid.cellCount());
  for (std::int64_t row = 0; row < base.grid.rows; ++row) {
    for (std::int64_t column = 0; column < base.grid.columns; ++column) {
      base.at(column, row) = float(slopedBase(base.grid.centreX(column), base.grid.centreY(row)));
    }
  }
  return base;
}

}  // namespace parallax::test
