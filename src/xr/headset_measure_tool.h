// The measurement tools in the headset (issue 24, item 4): the laser's picks make distances,
// heights and areas. They are the window's Measurement kinds, with its arithmetic, its printed
// line and its labels (measure/measurement.h, measure/measurement_overlay.h); this class only
// decides which picks make which measurement, as the window's measure_tool.cpp does for clicks.
//
// The controls (a headset has no Enter key and no panel):
//   trigger       adds the laser's point to the measurement being drawn. A distance and a height
//                 finish at their second point (a distance here is one segment).
//   tool button   (B, or Y on a left Touch controller) closes an area that has three or more
//                 points; otherwise it drops what is being drawn and selects the next tool:
//                 distance -> height -> area -> distance.
// Positions are the cloud's file coordinates in double, as everywhere in measure/.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "measure/measurement.h"

namespace parallax {

class HeadsetMeasureTool {
 public:
  // The tool the trigger uses: Distance, Height or Area.
  MeasurementKind kind() const { return current_.kind; }
  // The measurement being drawn (its kind is the tool's); no points when none is.
  const Measurement& inProgress() const { return current_; }

  // Adds a picked point; returns the measurement when this point finishes it.
  std::optional<Measurement> pick(const glm::dvec3& point);
  // The tool button: returns the area it closes, or std::nullopt when it selected the next tool.
  std::optional<Measurement> toolButton();

 private:
  Measurement current_{.kind = MeasurementKind::Distance};
};

}  // namespace parallax
