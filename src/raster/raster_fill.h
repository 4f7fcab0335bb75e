// Filling the gaps of a raster (--fill; volume's surface): every cell without a value that has
// cells with a value within `radius` (world units, between cell centres) gets their inverse
// distance weighted mean (power 2), computed from the original values only, so the result does
// not depend on the order cells are visited. Cells farther than `radius` from any value stay
// nodata: a gap wider than twice the radius keeps its middle empty rather than inventing a
// surface there.
#pragma once

#include <cstdint>

#include "raster/raster_image.h"

namespace parallax {

// The fill radius when none is given (--fill without --fill-radius), in cells.
inline constexpr double kDefaultFillCells = 10.0;

// Returns the number of cells filled. `radius` must be positive.
std::uint64_t fillNodata(RasterImage& image, double radius);

}  // namespace parallax
