// What a raster cell holds, gathered from the points as they stream past: one accumulator for a
// band of rows, so that memory is the band's cells whatever the cloud's size.
//
//   min, max     the lowest, highest z of the cell's points (a DTM: --classes 2 --value min;
//                a DSM: --returns first --value max)
//   mean         the mean z of the cell's points
//   idw          inverse distance to a power (2) of the points within `idw_radius` of the
//                cell's centre, as gdal_grid's invdist with radius1 = radius2: sum(z / d^2) /
//                sum(1 / d^2); a point closer than 1e-6.5 (d^2 < 1e-13) to the centre gives its z
//                alone (the first such point in file order); no point within the radius: nodata
//   count        the number of points (0 where none: a count, never nodata)
//   density      count / R^2, points per square unit (0 where none)
//   intensity    the mean intensity of the cell's points
//
// Every value but idw uses the cell rule of raster_grid.h (a point counts in exactly one cell).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/point_cloud.h"
#include "raster/raster_grid.h"

namespace parallax {

enum class RasterValue { Min, Max, Mean, Idw, Count, Density, Intensity };

// "min", "max", ...: the names of --value.
std::string_view rasterValueName(RasterValue value);
std::optional<RasterValue> rasterValueNamed(std::string_view name);
// "min|max|mean|idw|count|density|intensity" for messages.
std::string rasterValueNames();

class CellAccumulator {
 public:
  // Rows [first_row, last_row) of `grid`; `idw_radius` (> 0) is used by RasterValue::Idw only.
  CellAccumulator(const RasterGrid& grid, RasterValue value, std::int64_t first_row,
                  std::int64_t last_row, double idw_radius);

  // Memory one cell takes while points are gathered (for the band plan).
  static std::size_t bytesPerCell(RasterValue value);

  // The points of `chunk` (all of them: the caller filtered); those whose cells are outside the
  // band or the grid are left out. Intensity needs the chunk's intensity column.
  void addChunk(const PointCloud& chunk);
  void addPoint(double x, double y, double z, float intensity);

  // The points that fell in the band's cells (idw: in at least one cell's circle).
  std::uint64_t pointsUsed() const { return points_used_; }

  // The band's values, row-major from first_row, `nodata` in cells without a value.
  std::vector<float> values(float nodata) const;

 private:
  void addIdw(double x, double y, double z);

  RasterGrid grid_;
  RasterValue value_;
  std::int64_t first_row_ = 0, last_row_ = 0;
  double idw_radius_ = 0.0;
  std::vector<float> extreme_;        // min, max
  std::vector<double> sum_;           // mean, intensity; idw: sum of z / d^2
  std::vector<double> weight_;        // idw: sum of 1 / d^2
  std::vector<std::uint32_t> count_;  // mean, intensity, count, density; idw: 1 = exact hit
  std::uint64_t points_used_ = 0;
};

}  // namespace parallax
