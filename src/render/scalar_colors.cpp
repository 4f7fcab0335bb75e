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

constexpr std::array<std::pair<ColorRamp, std::string_view>, 3> kRamps{{
    {ColorRamp::Viridis, "viridis"},
    {ColorRamp::Rainbow, "rainbow"},
    {ColorRamp::Grey, "grey"},
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

std::uint8_t channel(double value_0_255) {
  return std::uint8_t(std::lround(std::clamp(value_0_255, 0.0, 255.0)));
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

Rgba8 rampColor(ColorRamp ramp, double t) {
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  switch (ramp) {
    case ColorRamp::Viridis: {
      const double scaled = t * double(kViridisStops.size() - 1);
      const std::size_t low = std::min(std::size_t(scaled), kViridisStops.size() - 2);
      const double f = scaled - double(low);
      const auto& a = kViridisStops[low];
      const auto& b = kViridisStops[low + 1];
      return {channel(a[0] + (b[0] - a[0]) * f), channel(a[1] + (b[1] - a[1]) * f),
              channel(a[2] + (b[2] - a[2]) * f), 255};
    }
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
  const ScalarRange range =
      coloring.range ? *coloring.range
                     : scalarRangeOf(cloud, coloring.field).value_or(ScalarRange{0.0, 1.0});
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
