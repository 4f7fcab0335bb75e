#include "raster/hillshade.h"

#include <cmath>
#include <numbers>

namespace parallax {

std::vector<std::uint8_t> hillshade(const RasterImage& elevation, const HillshadeLight& light) {
  const RasterGrid& grid = elevation.grid;
  std::vector<std::uint8_t> out(grid.cellCount(), 0);
  const double to_radians = std::numbers::pi / 180.0;
  const double azimuth = light.azimuth_degrees * to_radians;
  const double altitude = light.altitude_degrees * to_radians;
  // Horn's gradient is the 3 x 3 kernel's sums divided by 8 cells' widths: the 8 goes into z.
  const double z = light.z_factor / 8.0;
  const double sin_altitude = sin(altitude);
  const double cos_altitude_z = cos(altitude) * z;
  const double cos_azimuth_term = cos(azimuth) * cos_altitude_z;
  const double sin_azimuth_term = sin(azimuth) * cos_altitude_z;
  // Rows go south: the y step is -R, as GDAL's geotransform[5].
  const double inv_ew = 1.0 / grid.resolution;
  const double inv_ns = -1.0 / grid.resolution;
  const float nodata = elevation.nodata;
  for (std::int64_t row = 1; row + 1 < grid.rows; ++row) {
    for (std::int64_t column = 1; column + 1 < grid.columns; ++column) {
      // The window a b c / d e f / g h i, as gdaldem's afWin[0..8].
      double w[9];
      bool complete = true;
      for (int k = 0; k < 9 && complete; ++k) {
        const float v = elevation.at(column + k % 3 - 1, row + k / 3 - 1);
        complete = v != nodata;
        w[k] = v;
      }
      if (!complete) continue;
      const double x = ((w[0] + 2 * w[3] + w[6]) - (w[2] + 2 * w[5] + w[8])) * inv_ew;
      const double y = ((w[6] + 2 * w[7] + w[8]) - (w[0] + 2 * w[1] + w[2])) * inv_ns;
      const double cang = (sin_altitude - (y * cos_azimuth_term - x * sin_azimuth_term)) /
                          std::sqrt(1.0 + z * z * (x * x + y * y));
      const double shade = cang <= 0.0 ? 1.0 : 1.0 + 254.0 * cang;
      // A float written to a byte band is rounded to the nearest (GDALCopyWords).
      out[std::size_t(row) * std::size_t(grid.columns) + std::size_t(column)] =
          std::uint8_t(std::lround(std::min(255.0, shade)));
    }
  }
  return out;
}

}  // namespace parallax
