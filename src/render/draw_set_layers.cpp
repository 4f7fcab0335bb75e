#include "render/draw_set_layers.h"

namespace parallax {

DrawSet withLayer(const DrawSet& base, const DrawSet& layer) {
  DrawSet combined = base;
  combined.items.insert(combined.items.end(), layer.items.begin(), layer.items.end());
  combined.bounds.extend(layer.bounds);
  combined.has_colors = base.has_colors && layer.has_colors;
  combined.has_normals = base.has_normals && layer.has_normals;
  combined.has_intensity = base.has_intensity && layer.has_intensity;
  combined.has_classification = base.has_classification && layer.has_classification;
  combined.has_gps_time = base.has_gps_time && layer.has_gps_time;
  return combined;
}

}  // namespace parallax
