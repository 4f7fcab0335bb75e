// The measurement tools in the headset (issue 24, item 4): the laser's picks make points,
// distances, heights, areas, angles and profiles. They are the window's Measurement kinds, with
// its arithmetic, its printed line and its labels (measure/measurement.h,
// measure/measurement_overlay.h); this class only decides which picks make which measurement, as
// the window's measure_tool.cpp does for clicks.
//
// The controls (a headset has no Enter key and no panel):
//   trigger       adds the laser's point to the measurement being drawn. Every kind but the area
//                 finishes at its least number of points: a point at one, a distance, a height
//                 and a profile's section line at two, an angle at three (a distance here is one
//                 segment, a profile one straight section).
//   tool button   (B, or Y on a left Touch controller; a short press, see locomotion.h) closes an
//                 area that has three or more points; otherwise it drops what is being drawn and
//                 selects the next tool, in the window's order: distance -> height -> area ->
//                 angle -> profile -> point -> distance.
//   held          (the tool button held kLongPressSeconds) deletes the last finished measurement:
//                 the caller's document, not this class's (xr_view.cpp).
// Positions are the cloud's file coordinates in double, as everywhere in measure/.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "measure/measurement.h"

namespace parallax {

class HeadsetMeasureTool {
 public:
  // `profile_width`: the corridor's full width of the profiles it makes (view's --profile-width).
  explicit HeadsetMeasureTool(double profile_width = 1.0) : profile_width_(profile_width) {}

  // The tool the trigger uses.
  MeasurementKind kind() const { return current_.kind; }
  // The measurement being drawn (its kind is the tool's); no points when none is.
  const Measurement& inProgress() const { return current_; }

  // Adds a picked point; returns the measurement when this point finishes it.
  std::optional<Measurement> pick(const glm::dvec3& point);
  // The tool button: returns the area it closes, or std::nullopt when it selected the next tool.
  std::optional<Measurement> toolButton();

 private:
  double profile_width_;
  Measurement current_{.kind = MeasurementKind::Distance};
};

}  // namespace parallax
