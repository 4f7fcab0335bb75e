// Grey-scale morphology on elevation grids: the opening the morphological ground filters (SMRF,
// PMF) apply with windows of growing size.
//
// The structuring element is a square of (2r + 1) x (2r + 1) cells (Chebyshev radius r), clipped
// at the grid's edges. A square is separable, so an erosion or dilation is a sliding minimum or
// maximum along the rows and then along the columns, O(cells) whatever r (a monotone queue):
// a disk, as Pingel et al. 2013 use, costs O(cells r). The square reaches sqrt(2) r along its
// diagonals: the slope a window lets through is that much larger there (terrain/NOTES.md).
#pragma once

#include <cstddef>

#include "terrain/elevation_grid.h"

namespace parallax {

// Each cell the minimum (erosion) or maximum (dilation) over the square of radius `r` around it.
// The grid must be filled (no NaN).
ElevationGrid erode(const ElevationGrid& grid, std::size_t r);
ElevationGrid dilate(const ElevationGrid& grid, std::size_t r);
// Erosion then dilation: removes what is narrower than the window and higher than around it.
ElevationGrid open(const ElevationGrid& grid, std::size_t r);

}  // namespace parallax
