#include "xr/headset_measure_tool.h"

namespace parallax {

std::optional<Measurement> HeadsetMeasureTool::pick(const glm::dvec3& point) {
  current_.points.push_back(point);
  // Area is the one kind left open: the tool button closes it.
  if (current_.kind == MeasurementKind::Area ||
      current_.points.size() < minimumVertices(current_.kind)) {
    return std::nullopt;
  }
  Measurement done = current_;
  current_.points.clear();
  return done;
}

std::optional<Measurement> HeadsetMeasureTool::toolButton() {
  if (current_.kind == MeasurementKind::Area &&
      current_.points.size() >= minimumVertices(MeasurementKind::Area)) {
    Measurement done = current_;
    current_.points.clear();
    return done;
  }
  const MeasurementKind next = current_.kind == MeasurementKind::Distance ? MeasurementKind::Height
                               : current_.kind == MeasurementKind::Height
                                   ? MeasurementKind::Area
                                   : MeasurementKind::Distance;
  current_ = Measurement{.kind = next};
  return std::nullopt;
}

}  // namespace parallax
