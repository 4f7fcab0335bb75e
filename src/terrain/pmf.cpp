// PMF (pmf.h): the window series and the opening over filled cells.
#include "terrain/pmf.h"

#include <cmath>
#include <limits>

#include "terrain/morphology.h"

namespace parallax {

std::vector<PmfIteration> pmfIterations(const PmfParameters& p) {
  std::vector<PmfIteration> out;
  double window = 0.0;
  for (int k = 0; window < p.max_window_size; ++k) {
    window = p.exponential ? p.cell_size * (2.0 * std::pow(p.base, k) + 1.0)
                           : p.cell_size * (2.0 * (k + 1) * p.base + 1.0);
    double threshold =
        k == 0 ? p.initial_distance
               : p.slope * (window - out.back().window) * p.cell_size + p.initial_distance;
    if (threshold > p.max_distance) threshold = p.max_distance;
    out.push_back({window, std::size_t(std::floor(window / 2.0 / p.cell_size)), threshold});
  }
  return out;
}

ElevationGrid pmfOpen(const ElevationGrid& minimum, std::size_t radius) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Empty cells are +inf to the erosion (never the least) and -inf to the dilation (never the
  // greatest), which then reads only the erosions of filled cells.
  ElevationGrid low = minimum;
  for (double& v : low.values()) {
    if (ElevationGrid::empty(v)) v = kInf;
  }
  ElevationGrid eroded = erode(low, radius);
  for (std::size_t c = 0; c < eroded.cells(); ++c) {
    if (ElevationGrid::empty(minimum.values()[c])) eroded.values()[c] = -kInf;
  }
  ElevationGrid opened = dilate(eroded, radius);
  for (std::size_t c = 0; c < opened.cells(); ++c) {
    if (ElevationGrid::empty(minimum.values()[c])) opened.values()[c] = ElevationGrid::kEmpty;
  }
  return opened;
}

}  // namespace parallax
