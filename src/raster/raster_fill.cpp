#include "raster/raster_fill.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <vector>

namespace parallax {

std::uint64_t fillNodata(RasterImage& image, double radius) {
  assert(radius > 0.0 && "fillNodata: the radius must be positive");
  const RasterGrid& grid = image.grid;
  const auto reach = std::int64_t(std::floor(radius / grid.resolution));
  const double reach2 = (radius / grid.resolution) * (radius / grid.resolution);
  const std::vector<float> original = image.values;
  const float nodata = image.nodata;
  std::atomic<std::uint64_t> filled{0};
  tbb::parallel_for(std::int64_t(0), grid.rows, [&](std::int64_t row) {
    std::uint64_t filled_here = 0;
    for (std::int64_t column = 0; column < grid.columns; ++column) {
      const std::size_t cell = std::size_t(row) * std::size_t(grid.columns) + std::size_t(column);
      if (original[cell] != nodata) continue;
      double sum = 0.0, weight = 0.0;
      const std::int64_t r0 = std::max<std::int64_t>(0, row - reach);
      const std::int64_t r1 = std::min<std::int64_t>(grid.rows - 1, row + reach);
      const std::int64_t c0 = std::max<std::int64_t>(0, column - reach);
      const std::int64_t c1 = std::min<std::int64_t>(grid.columns - 1, column + reach);
      for (std::int64_t r = r0; r <= r1; ++r) {
        const double dr = double(r - row);
        for (std::int64_t c = c0; c <= c1; ++c) {
          const float v = original[std::size_t(r) * std::size_t(grid.columns) + std::size_t(c)];
          if (v == nodata) continue;
          const double dc = double(c - column);
          const double d2 = dr * dr + dc * dc;  // in cells; never 0 (the cell itself is empty)
          if (d2 > reach2) continue;
          sum += double(v) / d2;
          weight += 1.0 / d2;
        }
      }
      if (weight > 0.0) {
        image.values[cell] = float(sum / weight);
        ++filled_here;
      }
    }
    filled += filled_here;
  });
  return filled.load();
}

}  // namespace parallax
