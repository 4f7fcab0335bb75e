#include "raster/cell_accumulator.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace parallax {

namespace {

constexpr std::array<std::pair<RasterValue, std::string_view>, 7> kValueNames{{
    {RasterValue::Min, "min"},
    {RasterValue::Max, "max"},
    {RasterValue::Mean, "mean"},
    {RasterValue::Idw, "idw"},
    {RasterValue::Count, "count"},
    {RasterValue::Density, "density"},
    {RasterValue::Intensity, "intensity"},
}};

// gdal_grid's test for a point on the node itself (gdalgrid.cpp: dfR2 < 0.0000000000001).
constexpr double kExactHitSquared = 1e-13;

}  // namespace

std::string_view rasterValueName(RasterValue value) {
  for (const auto& [v, name] : kValueNames) {
    if (v == value) return name;
  }
  return "?";
}

std::optional<RasterValue> rasterValueNamed(std::string_view name) {
  for (const auto& [v, n] : kValueNames) {
    if (n == name) return v;
  }
  return std::nullopt;
}

std::string rasterValueNames() {
  std::string names;
  for (const auto& [v, name] : kValueNames) {
    if (!names.empty()) names += '|';
    names += name;
  }
  return names;
}

CellAccumulator::CellAccumulator(const RasterGrid& grid, RasterValue value, std::int64_t first_row,
                                 std::int64_t last_row, double idw_radius)
    : grid_(grid),
      value_(value),
      first_row_(first_row),
      last_row_(last_row),
      idw_radius_(idw_radius) {
  assert(first_row >= 0 && first_row < last_row && last_row <= grid.rows &&
         "CellAccumulator: the band must be a non-empty range of the grid's rows");
  assert((value != RasterValue::Idw || idw_radius > 0.0) &&
         "CellAccumulator: idw needs a positive radius");
  const std::size_t cells = std::size_t(last_row - first_row) * std::size_t(grid.columns);
  switch (value) {
    case RasterValue::Min:
      extreme_.assign(cells, std::numeric_limits<float>::infinity());
      break;
    case RasterValue::Max:
      extreme_.assign(cells, -std::numeric_limits<float>::infinity());
      break;
    case RasterValue::Mean:
    case RasterValue::Intensity:
      sum_.assign(cells, 0.0);
      count_.assign(cells, 0);
      break;
    case RasterValue::Count:
    case RasterValue::Density:
      count_.assign(cells, 0);
      break;
    case RasterValue::Idw:
      sum_.assign(cells, 0.0);
      weight_.assign(cells, 0.0);
      count_.assign(cells, 0);
      break;
  }
}

std::size_t CellAccumulator::bytesPerCell(RasterValue value) {
  switch (value) {
    case RasterValue::Min:
    case RasterValue::Max:
    case RasterValue::Count:
    case RasterValue::Density:
      return 4;
    case RasterValue::Mean:
    case RasterValue::Intensity:
      return 12;
    case RasterValue::Idw:
      return 20;
  }
  return 20;
}

void CellAccumulator::addChunk(const PointCloud& chunk) {
  if (value_ == RasterValue::Intensity && !chunk.hasIntensity()) {
    throw std::invalid_argument("--value intensity: the cloud has no intensity attribute");
  }
  for (std::size_t i = 0; i < chunk.count; ++i) {
    const float intensity = value_ == RasterValue::Intensity ? chunk.intensity[i] : 0.0f;
    addPoint(chunk.worldX(i), chunk.worldY(i), chunk.worldZ(i), intensity);
  }
}

void CellAccumulator::addPoint(double x, double y, double z, float intensity) {
  if (value_ == RasterValue::Idw) {
    addIdw(x, y, z);
    return;
  }
  const std::int64_t row = grid_.rowOf(y);
  const std::int64_t column = grid_.columnOf(x);
  if (row < first_row_ || row >= last_row_ || column < 0 || column >= grid_.columns) return;
  const std::size_t cell =
      std::size_t(row - first_row_) * std::size_t(grid_.columns) + std::size_t(column);
  ++points_used_;
  switch (value_) {
    case RasterValue::Min:
      extreme_[cell] = std::min(extreme_[cell], float(z));
      break;
    case RasterValue::Max:
      extreme_[cell] = std::max(extreme_[cell], float(z));
      break;
    case RasterValue::Mean:
      sum_[cell] += z;
      ++count_[cell];
      break;
    case RasterValue::Intensity:
      sum_[cell] += intensity;
      ++count_[cell];
      break;
    case RasterValue::Count:
    case RasterValue::Density:
      ++count_[cell];
      break;
    case RasterValue::Idw:
      break;
  }
}

void CellAccumulator::addIdw(double x, double y, double z) {
  // The cells whose centres lie within the radius: centre x = left + (c + 0.5) R.
  const double r = idw_radius_;
  const double res = grid_.resolution;
  const auto first_column =
      std::max<std::int64_t>(0, std::int64_t(std::ceil((x - r - grid_.left) / res - 0.5)));
  const auto last_column = std::min<std::int64_t>(
      grid_.columns - 1, std::int64_t(std::floor((x + r - grid_.left) / res - 0.5)));
  const auto first_row = std::max<std::int64_t>(
      first_row_, std::int64_t(std::ceil((grid_.top - (y + r)) / res - 0.5)));
  const auto last_row = std::min<std::int64_t>(
      last_row_ - 1, std::int64_t(std::floor((grid_.top - (y - r)) / res - 0.5)));
  bool used = false;
  const double r2 = r * r;
  for (std::int64_t row = first_row; row <= last_row; ++row) {
    const double dy = y - grid_.centreY(row);
    for (std::int64_t column = first_column; column <= last_column; ++column) {
      const double dx = x - grid_.centreX(column);
      const double d2 = dx * dx + dy * dy;
      // gdal_grid's search ellipse is closed: a point at exactly the radius counts.
      if (d2 > r2) continue;
      used = true;
      const std::size_t cell =
          std::size_t(row - first_row_) * std::size_t(grid_.columns) + std::size_t(column);
      if (count_[cell] != 0) continue;  // an exact hit already decided the cell
      if (d2 < kExactHitSquared) {
        count_[cell] = 1;
        sum_[cell] = z;
        continue;
      }
      const double w = 1.0 / d2;  // power 2: 1 / d^2
      sum_[cell] += w * z;
      weight_[cell] += w;
    }
  }
  if (used) ++points_used_;
}

std::vector<float> CellAccumulator::values(float nodata) const {
  const std::size_t cells = std::size_t(last_row_ - first_row_) * std::size_t(grid_.columns);
  std::vector<float> out(cells, nodata);
  const double cell_area = grid_.resolution * grid_.resolution;
  for (std::size_t i = 0; i < cells; ++i) {
    switch (value_) {
      case RasterValue::Min:
      case RasterValue::Max:
        if (std::isfinite(extreme_[i])) out[i] = extreme_[i];
        break;
      case RasterValue::Mean:
      case RasterValue::Intensity:
        if (count_[i] != 0) out[i] = float(sum_[i] / double(count_[i]));
        break;
      case RasterValue::Count:
        out[i] = float(count_[i]);
        break;
      case RasterValue::Density:
        out[i] = float(double(count_[i]) / cell_area);
        break;
      case RasterValue::Idw:
        if (count_[i] != 0) {
          out[i] = float(sum_[i]);
        } else if (weight_[i] > 0.0) {
          out[i] = float(sum_[i] / weight_[i]);
        }
        break;
    }
  }
  return out;
}

}  // namespace parallax
