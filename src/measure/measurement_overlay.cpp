#include "measure/measurement_overlay.h"

namespace parallax {

namespace {

void appendMeasurement(const Measurement& m, bool emphasised,
                       const MeasurementOverlayOptions& options, OverlayScene& scene) {
  const OverlayColor color = measurementColor(m.kind);
  if (m.points.size() >= 2) {
    OverlayPolyline line;
    line.points = m.points;
    line.closed = m.kind == MeasurementKind::Area && m.points.size() >= 3;
    line.color = color;
    line.width_px = emphasised ? 3.0f : 2.0f;
    scene.polylines.push_back(std::move(line));
  }
  if (m.kind == MeasurementKind::Height && m.points.size() == 2) {
    // The vertical and the horizontal leg of the height difference, as Potree draws them.
    const glm::dvec3 a = m.points[0], b = m.points[1];
    const glm::dvec3 corner = a.z < b.z ? glm::dvec3(a.x, a.y, b.z) : glm::dvec3(b.x, b.y, a.z);
    OverlayPolyline legs;
    legs.points = {a, corner, b};
    legs.color = {color[0], color[1], color[2], 0.6f};
    legs.width_px = 1.0f;
    scene.polylines.push_back(std::move(legs));
  }
  for (const glm::dvec3& p : m.points) {
    scene.markers.push_back({p, color, emphasised ? 11.0f : 8.0f});
  }
  if (options.labels) {
    for (MeasurementLabel& label : measurementLabels(m, options.decimals)) {
      scene.labels.push_back({label.anchor, std::move(label.text), {1, 1, 1, 1}});
    }
  }
}

}  // namespace

OverlayColor measurementColor(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Point:
      return {1.0f, 0.3f, 0.3f, 1.0f};
    case MeasurementKind::Distance:
      return {1.0f, 0.85f, 0.1f, 1.0f};
    case MeasurementKind::Height:
      return {0.3f, 1.0f, 0.4f, 1.0f};
    case MeasurementKind::Area:
      return {0.3f, 0.7f, 1.0f, 1.0f};
    case MeasurementKind::Angle:
      return {1.0f, 0.5f, 1.0f, 1.0f};
    case MeasurementKind::Profile:
      return {1.0f, 0.6f, 0.2f, 1.0f};
  }
  return {1, 1, 1, 1};
}

void appendMeasurementOverlay(const MeasurementDocument& document,
                              const MeasurementOverlayOptions& options, OverlayScene& scene) {
  for (std::size_t i = 0; i < document.measurements.size(); ++i) {
    appendMeasurement(document.measurements[i], options.selected == i, options, scene);
  }
  if (options.in_progress) appendMeasurement(*options.in_progress, true, options, scene);
  for (const Annotation& a : document.annotations) {
    scene.markers.push_back({a.position, {0.2f, 1.0f, 1.0f, 1.0f}, 10.0f});
    if (options.labels) scene.labels.push_back({a.position, a.label, {0.2f, 1.0f, 1.0f, 1.0f}});
  }
}

}  // namespace parallax
