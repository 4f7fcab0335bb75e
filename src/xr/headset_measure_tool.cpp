#include "xr/headset_measure_tool.h"

namespace parallax {

namespace {

// The window's order of the tools (viewer/measure_tool.h), from distance round to point.
MeasurementKind nextHeadsetTool(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Distance:
      return MeasurementKind::Height;
    case MeasurementKind::Height:
      return MeasurementKind::Area;
    case MeasurementKind::Area:
      return MeasurementKind::Angle;
    case MeasurementKind::Angle:
      return MeasurementKind::Profile;
    case MeasurementKind::Profile:
      return MeasurementKind::Point;
    case MeasurementKind::Point:
      break;
  }
  return MeasurementKind::Distance;
}

}  // namespace

std::optional<Measurement> HeadsetMeasureTool::pick(const glm::dvec3& point) {
  current_.points.push_back(point);
  // Area is the one kind left open: the tool button closes it.
  if (current_.kind == MeasurementKind::Area ||
      current_.points.size() < minimumVertices(current_.kind)) {
    return std::nullopt;
  }
  Measurement done = current_;
  if (done.kind == MeasurementKind::Profile) done.profile_width = profile_width_;
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
  current_ = Measurement{.kind = nextHeadsetTool(current_.kind)};
  return std::nullopt;
}

}  // namespace parallax
