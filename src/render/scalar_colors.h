// Colouring points by a scalar attribute (what `process` writes: distance, curvature; or any
// other numeric property a file carries), as CloudCompare's scalar-field display does: a ramp
// over a range of values, the range chosen from the data or given.
//
// The ramp is applied on the CPU when a cloud is uploaded: the cloud's colour column is replaced
// by the ramp's colours and both rasterizers draw it as `rgb`. Why not in the shaders: a scalar
// attribute would need its own section in every chunk's buffer and a ramp in both rasterizers'
// shaders, for a choice a user changes a few times a session; a re-upload of a whole cloud (the
// only kind coloured this way) takes well under a second at the viewer's budget.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/point_cloud.h"

namespace parallax {

enum class ColorRamp {
  Viridis,  // perceptually uniform, readable in grey and by most colour-blind readers
  Rainbow,  // blue-cyan-green-yellow-red ("jet"), what CloudCompare and most scanners show
  Grey,     // black to white
  // Diverging: blue through light grey to red, for signed values around zero (M3C2 and other
  // distances between epochs): Moreland's cool-warm end and middle colours.
  CoolWarm,
};

// "viridis", "rainbow" (also "jet"), "grey" (also "gray"), "coolwarm" (also "diverging");
// std::nullopt for an unknown name.
std::optional<ColorRamp> parseColorRamp(std::string_view name);
std::string_view colorRampName(ColorRamp ramp);
std::string colorRampNames();  // "viridis|rainbow|grey|coolwarm"
// A diverging ramp (its middle is the neutral colour): its automatic range is centred on zero.
bool isDiverging(ColorRamp ramp);

// The ramp's colour at t in [0, 1] (clamped), alpha 255. Viridis: matplotlib's published colours
// at 0, 1/4, 1/2, 3/4 and 1, linearly interpolated in between. Rainbow: each channel
// clamp(1.5 - |4t - c|) for c = 3 (red), 2 (green), 1 (blue). Grey: t in every channel.
// CoolWarm: (59, 76, 192) at 0, (221, 221, 221) at 1/2, (180, 4, 38) at 1, linear in between
// (Moreland 2009 interpolates in his Msh space; linear RGB between his three colours keeps the
// definition one line and differs from his by a few units at the quarters). Each channel is
// rounded to the nearest of 0..255.
Rgba8 rampColor(ColorRamp ramp, double t);

// The colour of a point whose value is NaN (no value): mid grey, whatever the ramp.
inline constexpr Rgba8 kNoValueColor{128, 128, 128, 255};

struct ScalarRange {
  double min = 0.0, max = 1.0;
  friend bool operator==(const ScalarRange&, const ScalarRange&) = default;
};

// Which part of a field's values the automatic range spans: from the `low`th to the `high`th
// percentile of its finite values (0 and 100: the smallest and the largest). 2 and 98 leave out
// the few outliers that would otherwise squeeze every other value into one colour.
struct ScalarPercentiles {
  double low = 0.0, high = 100.0;
  friend bool operator==(const ScalarPercentiles&, const ScalarPercentiles&) = default;
};

// What a cloud is coloured by; an empty `field` colours nothing (the colour mode applies).
struct ScalarColoring {
  std::string field;
  ColorRamp ramp = ColorRamp::Viridis;
  std::optional<ScalarRange> range;  // std::nullopt: automatic (scalarAutoRange)
  ScalarPercentiles percentiles;     // what the automatic range spans
  friend bool operator==(const ScalarColoring&, const ScalarColoring&) = default;
};

// The fields a cloud can be coloured by: "intensity" where it has intensity, then its scalar
// columns (ScalarColumn), in their order.
std::vector<std::string> scalarFieldNames(const PointCloud& cloud);

// The smallest and largest finite value of `field` in the cloud; std::nullopt when it has none
// (every value NaN, or no points). Throws std::invalid_argument for a field the cloud lacks,
// naming the fields it has.
std::optional<ScalarRange> scalarRangeOf(const PointCloud& cloud, const std::string& field);

// The `percentile`th (0..100) of `field`'s finite values, by nearest rank over the sorted values
// (index round(percentile / 100 * (n - 1))): 0 is the smallest, 100 the largest. std::nullopt
// when the field has no finite value; throws as scalarRangeOf for a field the cloud lacks and
// std::invalid_argument for percentiles outside 0..100 or low above high.
std::optional<ScalarRange> scalarPercentileRange(const PointCloud& cloud, const std::string& field,
                                                 const ScalarPercentiles& percentiles);

// The range a coloring without a given range uses: the field's percentile range; for a diverging
// ramp whose range holds values on both sides of zero, widened to be symmetric about zero (so
// that zero is the neutral middle colour). {0, 1} for a field without finite values.
ScalarRange scalarAutoRange(const PointCloud& cloud, const ScalarColoring& coloring);

// The position of `value` on a ramp over `range`: (value - min) / (max - min), clamped to [0, 1]
// (a value outside the range takes the nearer end's colour); 0.5 for an empty range (min = max).
double rampPosition(double value, const ScalarRange& range);

// Replaces the cloud's colours with `coloring`'s (range: the given one, else scalarAutoRange;
// NaN values kNoValueColor). Throws std::invalid_argument naming the field and the fields the
// cloud has where it lacks it, and a range whose min is not below its max. Returns the range used.
ScalarRange paintScalarField(PointCloud& cloud, const ScalarColoring& coloring);

}  // namespace parallax
