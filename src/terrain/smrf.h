// SMRF, the simple morphological filter of Pingel, Clarke and McBride (2013), "An improved simple
// morphological filter for the terrain classification of airborne LIDAR data", ISPRS Journal of
// Photogrammetry and Remote Sensing 77: 21-30. Parameters and defaults as PDAL's filters.smrf.
//
// In two parts, so that a caller can stream the points twice and hold only the grid:
// 1. the caller lowers a minimum surface (ElevationGrid::addMinimum) with every candidate point;
//    smrfSurface fills it, marks as objects the cells an opening of growing radius (1 cell up to
//    window / cell) lowers by more than slope x radius x cell from one radius to the next,
//    and returns the surface refilled from the cells that are not objects, with its slope;
// 2. smrfIsGround says of each point whether it lies within threshold + scalar x slope of that
//    surface (bilinear between cell centres).
#pragma once

#include "terrain/elevation_grid.h"

namespace parallax {

struct SmrfParameters {
  double cell = 1.0;       // the grid's cell edge (the cloud's units)
  double slope = 0.15;     // rise over run the terrain may have
  double window = 18.0;    // the largest window radius (units): the widest object removed
  double scalar = 1.25;    // elevation threshold's growth with the surface's slope
  double threshold = 0.5;  // elevation threshold (units)
};

struct SmrfSurface {
  ElevationGrid ground;  // the provisional ground surface (filled), the objects' cells refilled
  ElevationGrid slope;   // its slope, cell by cell
  std::size_t object_cells = 0;
};

// Fills `minimum` (the minimum surface, empty cells allowed) and runs the progressive opening.
// A grid without a single filled cell gives empty grids (no point is then ground).
SmrfSurface smrfSurface(ElevationGrid minimum, const SmrfParameters& parameters);

// Whether (x, y, z) is ground: |z - ground(x, y)| <= threshold + scalar * slope(x, y).
bool smrfIsGround(const SmrfSurface& surface, const SmrfParameters& parameters, double x, double y,
                  double z);

}  // namespace parallax
