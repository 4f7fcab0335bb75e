// CSF, the cloth simulation filter of Zhang, Qi, Wan, Wang, Xie, Wang and Yan (2016), "An easy-
// to-use airborne LiDAR data filtering method based on cloth simulation", Remote Sensing 8(6):
// 501. The cloud is turned upside down (z -> -z) and a cloth of particles on a grid falls onto it
// under gravity; particles that reach the surface stop, springs between neighbours keep the cloth
// from following narrow pits (the upside-down buildings and trees); points within the class
// threshold of the settled cloth are ground. Parameters and defaults as the authors' CSF library
// and CloudCompare's CSF plug-in: cloth resolution 0.5, rigidness 3, iterations 500, time step
// 0.65, class threshold 0.5, slope smoothing on.
//
// As built here (terrain/NOTES.md, what it shares with the paper and where it is its own):
// - the surface under particle (i, j) is the lowest point of cell (i, j) turned upside down
//   (the paper: the nearest point in xy), empty cells filled as ElevationGrid::fillEmpty does;
// - each time step: Verlet integration, z' = z + (z - z_prev) (1 - 0.01) - 0.2 dt^2 (the paper's
//   damping and gravity), a particle at or below the surface is set on it and stops; then
//   `rigidness` rounds over the springs (right and up neighbours, in cell order): each movable
//   end moves half the difference towards the other end (the paper's d = 1/2 b (p_i - p_0), b 0
//   for a stopped particle); the run ends when no movable particle moved more than 0.005 in a
//   step or after `iterations`;
// - slope smoothing: movable particles next to stopped ones within 0.3 of the surface are set on
//   it and stopped, outwards until none is left (the paper's post-processing of steep slopes);
// - a point is ground when |-z - cloth(x, y)| < class threshold (bilinear between particles).
#pragma once

#include <cstddef>

#include "terrain/elevation_grid.h"

namespace parallax {

struct CsfParameters {
  double resolution = 0.5;       // the cloth's particle spacing (units)
  int rigidness = 3;             // 1 steep slopes, 2 relief, 3 flat terrain: spring rounds a step
  int iterations = 500;          // time steps at most
  double time_step = 0.65;       // dt
  double class_threshold = 0.5;  // a point closer than this to the cloth is ground (units)
  bool slope_smoothing = true;
};

struct CsfCloth {
  ElevationGrid height;  // the settled cloth, upside down (the ground is -height)
  int steps = 0;         // time steps run
};

// Settles the cloth on `minimum` (the minimum surface, right side up, empty cells allowed). An
// empty grid gives an empty cloth (no point is then ground).
CsfCloth csfCloth(ElevationGrid minimum, const CsfParameters& parameters);

// Whether (x, y, z) is ground: |-z - cloth(x, y)| < class threshold.
bool csfIsGround(const CsfCloth& cloth, const CsfParameters& parameters, double x, double y,
                 double z);

}  // namespace parallax
