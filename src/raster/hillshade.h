// Shaded relief of an elevation raster (--hillshade), as `gdaldem hillshade` computes it with its
// defaults: Horn's (1981) 3 x 3 gradient, light from azimuth 315 (north-west) at altitude 45
// degrees, z factor 1, scale 1 (elevations in the grid's horizontal unit). A pixel is
// 1 + 254 cos(angle between the light and the normal), 1 where the cell faces away; 0 (no value)
// on the raster's border and next to a cell without a value, as gdaldem without -compute_edges.
// GDAL approximates 1 / sqrt with one Newton step from SSE's rsqrtss; this computes it exactly,
// so a pixel may differ from gdaldem's by one grey level where the value is close to x.5.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/raster_image.h"

namespace parallax {

struct HillshadeLight {
  double azimuth_degrees = 315.0;  // clockwise from north
  double altitude_degrees = 45.0;  // above the horizon
  double z_factor = 1.0;
};

// One byte a cell, rows from the top.
std::vector<std::uint8_t> hillshade(const RasterImage& elevation, const HillshadeLight& light = {});

}  // namespace parallax
