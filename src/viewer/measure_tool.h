// The viewer's measurement tools: which one a click uses (`view --tool NAME`, the panel's
// chooser). Point, distance, height, area, angle and profile add a picked point to the
// measurement being drawn; annotation places a labelled point (measure/measurement.h).
#pragma once

#include <optional>
#include <string_view>

namespace parallax {

enum class MeasureTool { None, Point, Distance, Height, Area, Angle, Profile, Annotation };

// "none", "point", "distance", "height", "area", "angle", "profile", "annotation".
std::string_view measureToolName(MeasureTool tool);
std::optional<MeasureTool> measureToolFromName(std::string_view name);

}  // namespace parallax
