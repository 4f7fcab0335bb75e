#include "raster/raster_layer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "raster/geotiff.h"
#include "raster/hillshade.h"

namespace parallax {

namespace {

std::uint8_t shaded(std::uint8_t channel, double factor) {
  return std::uint8_t(std::lround(std::clamp(double(channel) * factor, 0.0, 255.0)));
}

}  // namespace

std::pair<double, double> rasterValueRange(const RasterImage& raster) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const float v : raster.values) {
    if (v == raster.nodata || !std::isfinite(v)) continue;
    low = std::min(low, double(v));
    high = std::max(high, double(v));
  }
  if (low > high) return {0.0, 0.0};
  return {low, high};
}

PointCloud rasterLayerPoints(const RasterImage& raster, const RasterLayerLook& look) {
  const RasterGrid& grid = raster.grid;
  std::size_t count = 0;
  for (const float v : raster.values) count += v != raster.nodata && std::isfinite(v);
  const auto [low_value, high_value] = rasterValueRange(raster);

  PointCloud cloud;
  const double step = grid.resolution / 1000.0;
  cloud.quantization.scale = {step, step, step};
  cloud.quantization.offset = {grid.left, grid.bottom(), low_value};
  if (!cloud.quantization.fits(0, grid.right()) || !cloud.quantization.fits(1, grid.top) ||
      !cloud.quantization.fits(2, high_value)) {
    throw std::invalid_argument("raster of " + std::to_string(grid.columns) + " x " +
                                std::to_string(grid.rows) + " cells: too large to show as a layer");
  }
  cloud.count = count;
  cloud.positions = Column<Int3>(count);
  cloud.colors = Column<Rgba8>(count);

  const std::vector<std::uint8_t> shade = hillshade(raster);
  // Flat ground's hillshade (gdaldem's 1 + 254 cos(zenith) with the light at 45 degrees).
  const double flat = 1.0 + 254.0 * std::sin(45.0 * std::acos(-1.0) / 180.0);
  std::size_t i = 0;
  for (std::int64_t row = 0; row < grid.rows; ++row) {
    for (std::int64_t column = 0; column < grid.columns; ++column) {
      const float v = raster.at(column, row);
      if (v == raster.nodata || !std::isfinite(v)) continue;
      cloud.positions[i] = {cloud.quantization.toQuantized(0, grid.centreX(column)),
                            cloud.quantization.toQuantized(1, grid.centreY(row)),
                            cloud.quantization.toQuantized(2, double(v))};
      const double t = look.high > look.low
                           ? std::clamp((double(v) - look.low) / (look.high - look.low), 0.0, 1.0)
                           : 0.5;
      const std::uint8_t s =
          shade[std::size_t(row) * std::size_t(grid.columns) + std::size_t(column)];
      const double light = s == 0 ? flat : double(s);
      const double factor = look.ambient + (1.0 - look.ambient) * light / 255.0;
      const Rgba8 c = look.ramp(t);
      cloud.colors[i] = {shaded(c.r, factor), shaded(c.g, factor), shaded(c.b, factor), 255};
      ++i;
    }
  }
  cloud.computeBounds();
  return cloud;
}

PointCloud loadRasterLayer(const std::filesystem::path& path,
                           const std::function<Rgba8(double t)>& ramp) {
  const RasterImage raster = readRaster(path);
  const auto [low, high] = rasterValueRange(raster);
  return rasterLayerPoints(raster, {.ramp = ramp, .low = low, .high = high});
}

}  // namespace parallax
