// A raster shown with the cloud (raster/raster_layer.h): `view CLOUD --raster DEM.tif` and the
// panel's Raster layer section, which loads one by path (a GeoTIFF of `parallax raster`, or any
// single-band raster GDAL reads in the cloud's CRS), changes its ramp, or removes it.
#include <imgui.h>

#include <array>
#include <cstdio>
#include <exception>

#include "raster/raster_layer.h"
#include "render/scalar_colors.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

bool loadRasterLayer(Session& s, const std::filesystem::path& path) {
  try {
    const ColorRamp ramp = s.raster_ramp;
    const PointCloud points =
        parallax::loadRasterLayer(path, [ramp](double t) { return rampColor(ramp, t); });
    s.raster_layer = std::make_unique<GpuPointCloud>(points);
    s.raster_layer_cells = points.count;
    s.raster_path = path;
    s.raster_shown_ramp = ramp;
    s.raster_error.clear();
    s.drawn.reset();  // the next frame draws the layer
    std::fprintf(stderr, "parallax view: raster %s, %llu cells shown\n", path.string().c_str(),
                 static_cast<unsigned long long>(points.count));
    return true;
  } catch (const std::exception& e) {
    s.raster_error = e.what();
    std::fprintf(stderr, "parallax view: %s\n", e.what());
    return false;
  }
}

void drawRasterPanel(Session& s) {
  ImGui::Separator();
  ImGui::TextDisabled("Raster layer");
  ImGui::InputText("raster file", s.raster_path_text.data(), s.raster_path_text.size());
  const ColorRamp ramps[] = {ColorRamp::Viridis, ColorRamp::Rainbow, ColorRamp::Grey,
                             ColorRamp::CoolWarm};
  if (ImGui::BeginCombo("raster ramp", std::string(colorRampName(s.raster_ramp)).c_str())) {
    for (const ColorRamp ramp : ramps) {
      if (ImGui::Selectable(std::string(colorRampName(ramp)).c_str(), ramp == s.raster_ramp)) {
        s.raster_ramp = ramp;
      }
    }
    ImGui::EndCombo();
  }
  if (ImGui::Button("Load raster")) loadRasterLayer(s, s.raster_path_text.data());
  if (s.raster_layer) {
    ImGui::SameLine();
    if (ImGui::Button("Remove raster")) {
      s.raster_layer.reset();
      s.drawn.reset();
    } else if (s.raster_shown_ramp != s.raster_ramp) {
      loadRasterLayer(s, s.raster_path);  // the new ramp
    }
  }
  if (s.raster_layer) {
    ImGui::TextWrapped("%s: %llu cells", s.raster_path.filename().string().c_str(),
                       static_cast<unsigned long long>(s.raster_layer_cells));
  }
  if (!s.raster_error.empty()) ImGui::TextWrapped("%s", s.raster_error.c_str());
}

}  // namespace parallax::viewer_internal
