// PMF, the progressive morphological filter of Zhang, Chen, Whitman, Shyu, Yan and Zhang (2003),
// "A progressive morphological filter for removing nonground measurements from airborne LIDAR
// data", IEEE Transactions on Geoscience and Remote Sensing 41(4): 872-882. Parameters, defaults
// and window series as PCL's pcl::ProgressiveMorphologicalFilter (and Debian's
// pcl_progressive_morphological_filter), so that the two can be run with the same values.
//
// The paper works on the gridded minimum surface; PCL works on the points, a window being the
// points within a box of the window's width around each. Here: on the grid, each iteration
// against the points still taken for ground (as PCL's iterations are):
//   the minimum surface of the ground points so far (cells without one empty), opened with a
//   square of radius k cells (empty cells take no part); a ground point whose z is threshold or
//   more above the opening at its cell is no longer ground.
// With one point a cell (a gridded cloud) this is PCL's result exactly: a box of width
// cell (2k + 1) around a point holds the cells within k of its own (test
// PmfAgreesWithPcl...); with several points a cell PCL's windows are a point's own, and the two
// can differ at objects' edges.
#pragma once

#include <cstddef>
#include <vector>

#include "terrain/elevation_grid.h"

namespace parallax {

struct PmfParameters {
  double max_window_size = 33.0;   // the largest window's width (units)
  double slope = 0.7;              // terrain slope, for the thresholds
  double initial_distance = 0.15;  // the first window's height threshold (units)
  double max_distance = 10.0;      // the thresholds' cap (units)
  double cell_size = 1.0;          // the grid's cell edge (units)
  double base = 2.0;               // window growth
  bool exponential = true;         // window k: cell (2 base^k + 1); else cell (2 (k + 1) base + 1)
};

struct PmfIteration {
  double window = 0.0;     // the window's width (units), as PCL computes it
  std::size_t radius = 0;  // cells either side: floor(window / 2 / cell)
  double threshold = 0.0;  // height above the opening at which a point stops being ground
};

// The windows and thresholds, as PCL's extract() computes them: windows grow until one reaches
// max_window_size (that one included); threshold 0 is initial_distance, threshold k is
// slope * (window_k - window_k-1) * cell_size + initial_distance (PCL multiplies by the cell
// twice: windows are already in units), capped at max_distance.
std::vector<PmfIteration> pmfIterations(const PmfParameters& parameters);

// The opening of `minimum` (empty cells allowed) with a square of `radius` cells where empty
// cells take no part: a cell's erosion is the least filled value within the radius, its opening
// the greatest erosion of a filled cell within the radius. Empty cells stay empty.
ElevationGrid pmfOpen(const ElevationGrid& minimum, std::size_t radius);

}  // namespace parallax
