#include "render/scalar_colors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>

#include "core/column_names.h"

namespace parallax {

namespace {

constexpr std::array<std::pair<ColorRamp, std::string_view>, 4> kRamps{{
    {ColorRamp::Viridis, "viridis"},
    {ColorRamp::Rainbow, "rainbow"},
    {ColorRamp::Grey, "grey"},
    {ColorRamp::CoolWarm, "coolwarm"},
}};

// Matplotlib's viridis at t = 0, 0.25, 0.5, 0.75 and 1 (#440154, #3b528b, #21918c, #5ec962,
// #fde725), the colours its documentation and most tools quote.
constexpr std::array<std::array<double, 3>, 5> kViridisStops{{
    {68, 1, 84},
    {59, 82, 139},
    {33, 145, 140},
    {94, 201, 98},
    {253, 231, 37},
}};

// Moreland's "Diverging Color Maps for Scientific Visualization" (2009): the cool end, the
// neutral middle and the warm end.
constexpr std::array<std::array<double, 3>, 3> kCoolWarmStops{{
    {59, 76, 192},
    {221, 221, 221},
    {180, 4, 38},
}};

std::uint8_t channel(double value_0_255) {
  return std::uint8_t(std::lround(std::clamp(value_0_255, 0.0, 255.0)));
}

template <std::size_t N>
Rgba8 interpolateStops(const std::array<std::array<double, 3>, N>& stops, double t) {
  const double scaled = t * double(N - 1);
  const std::size_t low = std::min(std::size_t(scaled), N - 2);
  const double f = scaled - double(low);
  const auto& a = stops[low];
  const auto& b = stops[low + 1];
  return {channel(a[0] + (b[0] - a[0]) * f), channel(a[1] + (b[1] - a[1]) * f),
          channel(a[2] + (b[2] - a[2]) * f), 255};
}

std::string fieldList(const PointCloud& cloud) {
  const auto names = scalarFieldNames(cloud);
  if (names.empty()) return "none";
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// Point i's value of `field` (intensity or a scalar column) as double; `column` null: intensity.
double valueAt(const PointCloud& cloud, const ScalarColumn* column, std::size_t i) {
  return column ? column->valueAsDouble(i) : double(cloud.intensity[i]);
}

// The column of `field`, nullptr for intensity; throws for a field the cloud lacks.
const ScalarColumn* fieldColumn(const PointCloud& cloud, const std::string& field) {
  if (const ScalarColumn* column = cloud.findScalar(field)) return column;
  if (field == column_names::kIntensity && cloud.hasIntensity()) return nullptr;
  throw std::invalid_argument("--color " + field + ": the cloud has no attribute '" + field +
                              "' (scalar fields: " + fieldList(cloud) +
                              "; colour modes: rgb|elevation|intensity|normal|classification|"
                              "uniform)");
}

}  // namespace

std::optional<ColorRamp> parseColorRamp(std::string_view name) {
  if (name == "jet") return ColorRamp::Rainbow;
  if (name == "gray") return ColorRamp::Grey;
  if (name == "diverging") return ColorRamp::CoolWarm;
  for (const auto& [ramp, text] : kRamps) {
    if (text == name) return ramp;
  }
  return std::nullopt;
}

std::string_view colorRampName(ColorRamp ramp) {
  for (const auto& [value, text] : kRamps) {
    if (value == ramp) return text;
  }
  return "?";
}

std::string colorRampNames() {
  std::string text;
  for (const auto& [ramp, name] : kRamps) {
    if (!text.empty()) text += '|';
    text += name;
  }
  return text;
}

bool isDiverging(ColorRamp ramp) {
  return ramp == ColorRamp::CoolWarm;
}

Rgba8 rampColor(ColorRamp ramp, double t) {
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  switch (ramp) {
    case ColorRamp::Viridis:
      return interpolateStops(kViridisStops, t);
    case ColorRamp::CoolWarm:
      return interpolateStops(kCoolWarmStops, t);
    case ColorRamp::Rainbow: {
      const auto c = [t](double centre) {
        return channel(255.0 * std::clamp(1.5 - std::abs(4.0 * t - centre), 0.0, 1.0));
      };
      return {c(3.0), c(2.0), c(1.0), 255};
    }
    case ColorRamp::Grey: {
      const std::uint8_t v = channel(255.0 * t);
      return {v, v, v, 255};
    }
  }
  return kNoValueColor;
}

std::vector<std::string> scalarFieldNames(const PointCloud& cloud) {
  std::vector<std::string> names;
  if (cloud.hasIntensity()) names.emplace_back(column_names::kIntensity);
  for (const auto& column : cloud.scalars) names.push_back(column.name);
  return names;
}

std::optional<ScalarRange> scalarRangeOf(const PointCloud& cloud, const std::string& field) {
  const ScalarColumn* column = fieldColumn(cloud, field);
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const double v = valueAt(cloud, column, i);
    if (!std::isfinite(v)) continue;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  if (low > high) return std::nullopt;
  return ScalarRange{low, high};
}

std::optional<ScalarRange> scalarPercentileRange(const PointCloud& cloud, const std::string& field,
                                                 const ScalarPercentiles& percentiles) {
  if (!(percentiles.low >= 0.0 && percentiles.high <= 100.0 &&
        percentiles.low <= percentiles.high)) {
    throw std::invalid_argument("--color-percentiles " + std::to_string(percentiles.low) + "," +
                                std::to_string(percentiles.high) +
                                ": percentiles run from 0 to 100, the low one first");
  }
  if (percentiles.low == 0.0 && percentiles.high == 100.0) return scalarRangeOf(cloud, field);
  const ScalarColumn* column = fieldColumn(cloud, field);
  std::vector<double> values;
  values.reserve(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const double v = valueAt(cloud, column, i);
    if (std::isfinite(v)) values.push_back(v);
  }
  if (values.empty()) return std::nullopt;
  // Nearest rank: nth_element twice, O(n), the second on the part above the first.
  const auto rank = [&](double percentile) {
    return std::size_t(std::lround(percentile / 100.0 * double(values.size() - 1)));
  };
  const std::size_t low = rank(percentiles.low), high = rank(percentiles.high);
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(low), values.end());
  const double low_value = values[low];
  std::nth_element(values.begin() + std::ptrdiff_t(low), values.begin() + std::ptrdiff_t(high),
                   values.end());
  return ScalarRange{low_value, values[high]};
}

ScalarRange scalarAutoRange(const PointCloud& cloud, const ScalarColoring& coloring) {
  ScalarRange range = scalarPercentileRange(cloud, coloring.field, coloring.percentiles)
                          .value_or(ScalarRange{0.0, 1.0});
  if (isDiverging(coloring.ramp) && range.min < 0.0 && range.max > 0.0) {
    const double reach = std::max(-range.min, range.max);
    range = {-reach, reach};
  }
  return range;
}

double rampPosition(double value, const ScalarRange& range) {
  if (!(range.max > range.min)) return 0.5;
  return std::clamp((value - range.min) / (range.max - range.min), 0.0, 1.0);
}

ScalarRange paintScalarField(PointCloud& cloud, const ScalarColoring& coloring) {
  const ScalarColumn* column = fieldColumn(cloud, coloring.field);
  if (coloring.range && !(coloring.range->min < coloring.range->max)) {
    throw std::invalid_argument("--color-range " + std::to_string(coloring.range->min) + "," +
                                std::to_string(coloring.range->max) +
                                ": the minimum must be below the maximum");
  }
  const ScalarRange range = coloring.range ? *coloring.range : scalarAutoRange(cloud, coloring);
  if (cloud.colors.size() != cloud.count) cloud.colors = Column<Rgba8>(cloud.count);
  Rgba8* colors = cloud.colors.data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cloud.count), [&](const auto& block) {
    for (std::size_t i = block.begin(); i != block.end(); ++i) {
      const double v = valueAt(cloud, column, i);
      colors[i] = std::isnan(v) ? kNoValueColor : rampColor(coloring.ramp, rampPosition(v, range));
    }
  });
  return range;
}

}  // namespace parallax
