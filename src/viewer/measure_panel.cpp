// The panel's Measure section: the tool chooser, the measurement being drawn with its values as
// they grow, the list of measurements (rename, select, delete), the selected profile's plot and
// exports, the annotations (rename, fly to, delete), and Save / Load of the measurement file.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <string>

#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

constexpr std::array<MeasureTool, 8> kTools{
    MeasureTool::None, MeasureTool::Point, MeasureTool::Distance, MeasureTool::Height,
    MeasureTool::Area, MeasureTool::Angle, MeasureTool::Profile,  MeasureTool::Annotation};

// The values of a measurement, one line each: every segment and the total, dz, the areas, the
// angle, as they apply to its kind.
void showValues(const Measurement& m) {
  const MeasurementValues v = measurementValues(m);
  switch (m.kind) {
    case MeasurementKind::Point:
      for (const glm::dvec3& p : m.points) ImGui::Text("%.3f  %.3f  %.3f", p.x, p.y, p.z);
      break;
    case MeasurementKind::Distance:
    case MeasurementKind::Profile:
      for (std::size_t i = 0; i < v.segments.size(); ++i) {
        ImGui::TextWrapped("segment %zu: %.3f m 3D", i + 1, v.segments[i]);
      }
      // Wrapped, never cut: the panel may be narrower than the line.
      ImGui::TextWrapped("total %.3f m 3D, %.3f m horizontal, dz %.3f m", v.total, v.horizontal,
                         v.dz);
      if (m.kind == MeasurementKind::Profile) {
        ImGui::TextWrapped("corridor %.3f m wide", m.profile_width);
      }
      break;
    case MeasurementKind::Height:
      ImGui::TextWrapped("dz %.3f m, horizontal %.3f m, 3D %.3f m", v.dz, v.horizontal, v.total);
      break;
    case MeasurementKind::Area:
      ImGui::TextWrapped("area 3D %.3f m², on the ground %.3f m²", v.area_3d, v.area_projected);
      ImGui::TextWrapped("perimeter %.3f m 3D (%zu edges)", v.total, v.segments.size());
      break;
    case MeasurementKind::Angle:
      ImGui::Text("angle %.2f°", v.angle_deg);
      break;
  }
}

// The profile as a scatter plot of (station, height), heights scaled to the plot's box.
void plotProfile(const HeightProfile& profile) {
  const ImVec2 size(std::max(ImGui::GetContentRegionAvail().x, 120.0f), 140.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, {origin.x + size.x, origin.y + size.y}, IM_COL32(20, 20, 24, 255));
  ImGui::Dummy(size);
  if (profile.samples.empty()) return;
  double s0 = profile.samples.front().station, s1 = profile.samples.back().station;
  const auto [z0, z1] = heightRange(profile);
  const double ds = std::max(s1 - s0, 1e-9), dz = std::max(z1 - z0, 1e-9);
  // The same scale on both axes where it fits, as a section drawing would; else stretched.
  const float margin = 4.0f;
  const float w = size.x - 2 * margin, h = size.y - 2 * margin;
  // At most a few thousand dots: a plot, not a point renderer.
  const std::size_t step = std::max<std::size_t>(1, profile.samples.size() / 4000);
  for (std::size_t i = 0; i < profile.samples.size(); i += step) {
    const ProfileSample& p = profile.samples[i];
    const float x = origin.x + margin + float((p.station - s0) / ds) * w;
    const float y = origin.y + margin + h - float((p.position.z - z0) / dz) * h;
    draw->AddRectFilled({x, y}, {x + 2, y + 2}, IM_COL32(255, 160, 50, 255));
  }
  // Stations are horizontal distances along the line (the plot's x axis).
  ImGui::TextWrapped("%.3f m horizontal along the line, heights %.3f .. %.3f m", s1 - s0, z0, z1);
}

}  // namespace

void drawMeasurePanel(Session& s) {
  MeasureSession& m = s.measure;
  if (!ImGui::CollapsingHeader("Measure", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::PushID("measure");
  MeasureTool tool = m.tool;
  if (ImGui::BeginCombo("tool", std::string(measureToolName(tool)).c_str())) {
    for (MeasureTool option : kTools) {
      if (ImGui::Selectable(std::string(measureToolName(option)).c_str(), option == tool)) {
        setMeasureTool(s, option);
      }
    }
    ImGui::EndCombo();
  }
  if (m.tool == MeasureTool::Profile) {
    ImGui::InputDouble("width (m)", &m.profile_width, 0.1, 1.0, "%.3f");
    m.profile_width = std::max(m.profile_width, 1e-3);
  }
  if (m.tool == MeasureTool::Annotation) {
    ImGui::InputText("label", &m.annotation_label);
    ImGui::Checkbox("save the camera with it", &m.annotation_camera);
  }
  if (m.tool != MeasureTool::None) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("click points (Enter finishes, Backspace removes, Esc cancels)");
    ImGui::PopStyleColor();
  }
  if (!m.current.points.empty()) {
    ImGui::Separator();
    ImGui::Text("%s a %s, %zu points", m.editing ? "editing" : "drawing",
                std::string(measurementKindName(m.current.kind)).c_str(), m.current.points.size());
    showValues(m.current);
    // Each vertex, with a button that removes it.
    std::optional<std::size_t> remove_vertex;
    for (std::size_t i = 0; i < m.current.points.size(); ++i) {
      const glm::dvec3& p = m.current.points[i];
      ImGui::PushID(int(2000 + i));
      if (ImGui::SmallButton("x")) remove_vertex = i;
      ImGui::SameLine();
      ImGui::Text("%zu: %.3f  %.3f  %.3f", i + 1, p.x, p.y, p.z);
      ImGui::PopID();
    }
    if (remove_vertex) removeMeasurePoint(s, *remove_vertex);
    if (ImGui::Button("Finish")) finishMeasurement(s);
    ImGui::SameLine();
    if (ImGui::Button("Remove last point")) removeLastMeasurePoint(s);
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) cancelMeasurement(s);
  }

  if (!m.document.measurements.empty()) {
    ImGui::Separator();
    ImGui::Text("%zu measurements", m.document.measurements.size());
    for (std::size_t i = 0; i < m.document.measurements.size(); ++i) {
      const Measurement& item = m.document.measurements[i];
      const std::string text =
          std::to_string(i + 1) + ". " +
          (item.name.empty() ? std::string(measurementKindName(item.kind)) : item.name);
      ImGui::PushID(int(i));
      if (ImGui::Selectable(text.c_str(), m.selected == i)) {
        m.selected = m.selected == i ? std::nullopt : std::optional<std::size_t>(i);
      }
      // The values below the name, wrapped: a Selectable would cut them at the panel's edge.
      ImGui::Indent();
      ImGui::TextWrapped("%s", describeMeasurement(item, 3).c_str());
      ImGui::Unindent();
      ImGui::PopID();
    }
  }
  if (m.selected && *m.selected < m.document.measurements.size()) {
    Measurement& selected = m.document.measurements[*m.selected];
    ImGui::Separator();
    ImGui::InputText("name", &selected.name);
    showValues(selected);
    if (selected.kind == MeasurementKind::Profile) {
      ImGui::InputDouble("corridor width", &selected.profile_width, 0.1, 1.0, "%.3f");
      selected.profile_width = std::max(selected.profile_width, 1e-3);
      if (const MeasureSession::Profile* profile = selectedProfile(s)) {
        if (!profile->error.empty()) {
          ImGui::TextWrapped("profile: %s", profile->error.c_str());
        } else {
          ImGui::TextWrapped("%zu points, from %s", profile->profile.samples.size(),
                             profile->source.c_str());
          plotProfile(profile->profile);
          if (ImGui::Button("Export CSV (Ctrl+X)")) exportProfile(s, false);
          ImGui::SameLine();
          if (ImGui::Button("Export LAS (Ctrl+Shift+X)")) exportProfile(s, true);
        }
      }
    }
    drawVolumePanel(s);
    if (ImGui::Button("Edit points (Ctrl+E)")) editSelectedMeasurement(s);
    ImGui::SameLine();
    if (ImGui::Button("Delete measurement")) deleteSelectedMeasurement(s);
  }

  if (!m.document.annotations.empty()) {
    ImGui::Separator();
    ImGui::Text("%zu annotations", m.document.annotations.size());
    std::optional<std::size_t> remove;
    for (std::size_t i = 0; i < m.document.annotations.size(); ++i) {
      Annotation& a = m.document.annotations[i];
      ImGui::PushID(int(1000 + i));
      if (ImGui::Button("Fly to")) flyToAnnotation(s, a);
      ImGui::SameLine();
      if (ImGui::Button("x")) remove = i;
      ImGui::SameLine();
      ImGui::SetNextItemWidth(160);
      ImGui::InputText("##label", &a.label);
      ImGui::PopID();
    }
    if (remove)
      m.document.annotations.erase(m.document.annotations.begin() + std::ptrdiff_t(*remove));
  }

  ImGui::Separator();
  ImGui::InputText("file", &m.file);
  if (ImGui::Button("Save (Ctrl+S)")) saveMeasurements(s);
  ImGui::SameLine();
  if (ImGui::Button("Load")) loadMeasurements(s);
  ImGui::PopID();
}

}  // namespace parallax::viewer_internal
