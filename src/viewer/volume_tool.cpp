// The Volume tool of the measurement panel: cut, fill and net volume inside the selected area
// measurement, between the surface of the file shown and a base (the plane through the surface
// along the polygon's ring, the lowest point of the ring, or a raster file: a DTM, an earlier
// epoch), computed by `parallax volume`'s own call (raster/volume.h computeVolume: the surface
// rastered at the panel's resolution, only the cells whose centre is inside the polygon; a base
// raster checked there for its file, CRS and extent). The polygon is the area's vertices seen
// from above (their x and y): the picked points, in the file's coordinates.
//
// The base raster is a typed path: the viewer has no file dialog (GLFW has none, and Debian's
// ImGui 1.86 no file browser); a dropped file opens as the cloud shown, as everywhere else.
// An error is shown in the Volume part, at the panel's top and, with the panel hidden, over the
// picture (drawErrorBanner), where the failures to open a file are shown.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

std::string volumeBaseName(const MeasureSession& m) {
  switch (m.volume_base) {
    case VolumeBase::Plane:
      return "plane";
    case VolumeBase::Lowest:
      return "lowest";
    case VolumeBase::Raster:
      return "raster " + m.volume_base_file;
  }
  return "?";
}

const Measurement* selectedArea(const Session& s) {
  const MeasureSession& m = s.measure;
  if (!m.selected || *m.selected >= m.document.measurements.size()) return nullptr;
  const Measurement& measurement = m.document.measurements[*m.selected];
  return measurement.kind == MeasurementKind::Area ? &measurement : nullptr;
}

}  // namespace

const std::string* volumeError(const Session& s) {
  const MeasureSession& m = s.measure;
  const Measurement* area = selectedArea(s);
  if (!area || !m.volume || m.volume->error.empty()) return nullptr;
  if (m.volume->measurement != *m.selected || !(m.volume->of == *area)) return nullptr;
  return &m.volume->error;
}

void computeSelectedVolume(Session& s) {
  MeasureSession& m = s.measure;
  const Measurement* area = selectedArea(s);
  if (!area) {
    s.status = "volume: select an area measurement first (its polygon bounds the volume)";
    std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
    return;
  }
  MeasureSession::Volume volume;
  volume.measurement = *m.selected;
  volume.of = *area;
  try {
    // The file itself, read again (streamed: the surface is rastered out of core), so that the
    // volume is the one `parallax volume` gives for it; an octree or a URL is not one file.
    if (s.cloud_file.empty() && (s.octree || s.shown_path.empty() || s.build)) {
      throw std::invalid_argument(
          "needs a point file shown whole (an octree, a URL or a preview is not rastered here: "
          "use parallax volume on the file)");
    }
    VolumeOptions options;
    options.input.path = s.cloud_file.empty() ? s.shown_path : s.cloud_file;
    for (const glm::dvec3& p : area->points) options.polygon.push_back({p.x, p.y});
    options.resolution = m.volume_resolution;
    options.base = m.volume_base;
    if (m.volume_base == VolumeBase::Raster) {
      if (m.volume_base_file.empty()) {
        throw std::invalid_argument("base raster: type its path (a DTM GeoTIFF) in the field");
      }
      options.base_raster = m.volume_base_file;
    }
    volume.report = computeVolume(options);
    const VolumeReport& r = volume.report;
    char line[1400];
    std::snprintf(line, sizeof line,
                  "volume of measurement %zu: cut %.6f fill %.6f net %.6f (area %.6f, %llu cells "
                  "of %.6g, base %s)",
                  volume.measurement + 1, r.cut, r.fill, r.net, r.area,
                  static_cast<unsigned long long>(r.cells), m.volume_resolution,
                  volumeBaseName(m).c_str());
    s.status = line;
  } catch (const std::exception& e) {
    volume.error = e.what();
    s.status = "volume: " + volume.error;
  }
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
  m.volume = std::move(volume);
}

void drawVolumePanel(Session& s) {
  MeasureSession& m = s.measure;
  const Measurement* area = selectedArea(s);
  if (!area) return;
  ImGui::Separator();
  ImGui::TextDisabled("Volume");
  ImGui::InputDouble("cell size", &m.volume_resolution, 0.1, 1.0, "%.3f");
  m.volume_resolution = std::max(m.volume_resolution, 1e-3);
  int base = int(m.volume_base);
  ImGui::RadioButton("base: plane along the polygon", &base, int(VolumeBase::Plane));
  ImGui::SameLine();
  ImGui::RadioButton("lowest", &base, int(VolumeBase::Lowest));
  ImGui::SameLine();
  ImGui::RadioButton("raster", &base, int(VolumeBase::Raster));
  m.volume_base = VolumeBase(base);
  if (m.volume_base == VolumeBase::Raster) {
    ImGui::InputTextWithHint("base raster", "path of a DTM GeoTIFF, in the cloud's CRS",
                             &m.volume_base_file);
  }
  if (ImGui::Button("Compute the volume (Ctrl+V)")) computeSelectedVolume(s);
  // The last result, while it is the selected measurement's as it is now (an edit makes it old).
  if (const std::string* error = volumeError(s)) {
    drawErrorText(*error);
  } else if (m.volume && m.volume->measurement == *m.selected && m.volume->of == *area) {
    const VolumeReport& r = m.volume->report;
    ImGui::TextWrapped("cut %.3f m³, fill %.3f m³, net %.3f m³", r.cut, r.fill, r.net);
    ImGui::TextWrapped("over %.3f m² (%llu cells; %llu filled, %llu without surface)", r.area,
                       static_cast<unsigned long long>(r.cells),
                       static_cast<unsigned long long>(r.cells_filled),
                       static_cast<unsigned long long>(r.cells_without_surface));
    if (r.cells_without_base > 0) {
      ImGui::TextWrapped("%llu cells left out: the base raster has no value there",
                         static_cast<unsigned long long>(r.cells_without_base));
    }
  }
}

}  // namespace parallax::viewer_internal
