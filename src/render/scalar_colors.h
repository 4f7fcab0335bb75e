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
};

// "viridis", "rainbow" (also "jet"), "grey" (also "gray"); std::nullopt for an unknown name.
std::optional<ColorRamp> parseColorRamp(std::string_view name);
std::string_view colorRampName(ColorRamp ramp);
std::string colorRampNames();  // "viridis|rainbow|grey"

// The ramp's colour at t in [0, 1] (clamped), alpha 255. Viridis: matplotlib's published colours
// at 0, 1/4, 1/2, 3/4 and 1, linearly interpolated in between. Rainbow: each channel
// clamp(1.5 - |4t - c|) for c = 3 (red), 2 (green), 1 (blue). Grey: t in every channel. Each
// channel is rounded to the nearest of 0..255.
Rgba8 rampColor(ColorRamp ramp, double t);

// The colour of a point whose value is NaN (no value): mid grey, whatever the ramp.
inline constexpr Rgba8 kNoValueColor{128, 128, 128, 255};

struct ScalarRange {
  double min = 0.0, max = 1.0;
  friend bool operator==(const ScalarRange&, const ScalarRange&) = default;
};

// What a cloud is coloured by; an empty `field` colours nothing (the colour mode applies).
struct ScalarColoring {
  std::string field;
  ColorRamp ramp = ColorRamp::Viridis;
  std::optional<ScalarRange> range;  // std::nullopt: the field's own (scalarRangeOf)
  friend bool operator==(const ScalarColoring&, const ScalarColoring&) = default;
};

// The fields a cloud can be coloured by: "intensity" where it has intensity, then its scalar
// columns (ScalarColumn), in their order.
std::vector<std::string> scalarFieldNames(const PointCloud& cloud);

// The smallest and largest finite value of `field` in the cloud; std::nullopt when it has none
// (every value NaN, or no points). Throws std::invalid_argument for a field the cloud lacks,
// naming the fields it has.
std::optional<ScalarRange> scalarRangeOf(const PointCloud& cloud, const std::string& field);

// The position of `value` on a ramp over `range`: (value - min) / (max - min), clamped to [0, 1]
// (a value outside the range takes the nearer end's colour); 0.5 for an empty range (min = max).
double rampPosition(double value, const ScalarRange& range);

// Replaces the cloud's colours with `coloring`'s (range: the given one, else the field's own;
// NaN values kNoValueColor). Throws std::invalid_argument naming the field and the fields the
// cloud has where it lacks it, and a range whose min is not below its max. Returns the range used.
ScalarRange paintScalarField(PointCloud& cloud, const ScalarColoring& coloring);

}  // namespace parallax
