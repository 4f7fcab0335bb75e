// A raster shown with a cloud (`view CLOUD --raster DEM.tif`, `render --raster`): every cell with
// a value becomes a point at its centre, at its value's height, coloured by a ramp over the
// raster's values and shaded by its hillshade (raster/hillshade.h), so that the layer is drawn by
// the same rasterizers, in the same views, depth-tested against the cloud, as the cloud is.
//
// Why points and not a triangle mesh: both rasterizers, eye-dome lighting, stereo, the XR views
// and picking already take point chunks; a mesh would need a pass of its own in each. The cells
// are a regular lattice, so each point's local spacing is the cell size and the viewer's adaptive
// size closes the surface; at a fixed size of a few pixels it shows as a dotted surface when the
// camera comes closer than a cell a few pixels wide.
#pragma once

#include <filesystem>
#include <functional>
#include <utility>

#include "core/point_cloud.h"
#include "raster/raster_image.h"

namespace parallax {

struct RasterLayerLook {
  // The ramp's colour at t in [0, 1] (render/scalar_colors.h rampColor with the chosen ramp).
  std::function<Rgba8(double t)> ramp;
  // Low and high value of the ramp: t = (value - low) / (high - low), clamped; low = high
  // (a flat raster): t = 0.5. Defaults to the raster's smallest and largest value (rasterValueRange).
  double low = 0.0, high = 1.0;
  // The share of a cell's colour that does not depend on the light: colour x (ambient +
  // (1 - ambient) x hillshade / 255). A cell without a hillshade (the raster's border, next to a
  // cell without a value) takes the hillshade of flat ground, 1 + 254 sin(45 degrees).
  double ambient = 0.4;
};

// The smallest and largest value of the cells that have one; {0, 0} for a raster without any.
std::pair<double, double> rasterValueRange(const RasterImage& raster);

// The layer's points: one per cell with a value, at (centreX, centreY, value), quantized at a
// thousandth of the cell size from the grid's corner; colours as `look` says. Cells in row-major
// order from the top row (the upload sorts them again). Throws std::invalid_argument where the
// grid's coordinates do not fit 32-bit integers at that scale (a grid of over 2 M cells a side).
PointCloud rasterLayerPoints(const RasterImage& raster, const RasterLayerLook& look);

// Band 1 of the raster at `path` (raster/geotiff.h readRaster: any single-band raster GDAL
// reads, in the cloud's CRS), as the layer's points over its own value range with `ramp`.
// Throws InputError naming the file where GDAL cannot read it.
PointCloud loadRasterLayer(const std::filesystem::path& path,
                           const std::function<Rgba8(double t)>& ramp);

}  // namespace parallax
