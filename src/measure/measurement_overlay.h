// Measurements and annotations as overlay primitives (render/overlay.h): each measurement's
// lines and vertex markers in its kind's colour, the labels of measurement.h
// (measurementLabels), an annotation as a marker with its label.
#pragma once

#include <optional>

#include "measure/measurement_document.h"
#include "render/overlay.h"

namespace parallax {

struct MeasurementOverlayOptions {
  // The measurement being drawn (not yet in the document), shown brighter; may be none.
  const Measurement* in_progress = nullptr;
  // The index of the measurement selected in the panel, drawn wider.
  std::optional<std::size_t> selected;
  bool labels = true;
  int decimals = 2;
};

OverlayColor measurementColor(MeasurementKind kind);

// Appends the document's measurements and annotations to `scene`.
void appendMeasurementOverlay(const MeasurementDocument& document,
                              const MeasurementOverlayOptions& options, OverlayScene& scene);

}  // namespace parallax
