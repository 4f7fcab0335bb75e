// The viewer panel's "Filters" section: which classes are drawn (with the classification colour
// mode's legend), and a clip box. Everything
// here edits RenderSettings::filter, which the rasterizers read as uniforms: a change redraws
// the picture (the settings differ from the drawn ones) and uploads nothing.
#include <imgui.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

#include "core/classification.h"
#include "render/class_colors.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

// Bit c of `words`.
bool hasBit(const std::array<std::uint32_t, 8>& words, int c) {
  return (words[std::size_t(c) / 32] >> (c % 32)) & 1u;
}

void setBit(std::array<std::uint32_t, 8>& words, int c) {
  words[std::size_t(c) / 32] |= 1u << (c % 32);
}

void drawClassCheckboxes(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  PointFilter& filter = s.settings.filter;
  if (!e.classified) {
    ImGui::TextWrapped("no classification: every point is class 0 (never classified)");
  }
  if (ImGui::Button("all")) {
    for (int c = 0; c < 256; ++c) filter.setClass(c, true);
  }
  ImGui::SameLine();
  if (ImGui::Button("none")) {
    for (int c = 0; c < 256; ++c) filter.setClass(c, false);
  }
  for (int c = 0; c < 256; ++c) {
    if (!hasBit(e.listed, c)) continue;
    // The legend of the classification colour mode beside each name.
    const std::array<float, 3> rgb = classColor(c);
    ImGui::PushID(c);
    ImGui::ColorButton("##colour", ImVec4(rgb[0], rgb[1], rgb[2], 1.0f),
                       ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop);
    ImGui::PopID();
    ImGui::SameLine();
    bool keep = filter.keepsClass(c);
    // "2 ground", or "class 19" where ASPRS has no name (not "19 class 19").
    const std::string_view name = asprsClassName(c);
    const std::string label =
        name.empty() ? classLabel(c) : std::to_string(c) + " " + std::string(name);
    if (ImGui::Checkbox(label.c_str(), &keep)) filter.setClass(c, keep);
  }
}

void drawClipBoxEditor(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  bool changed = ImGui::Checkbox("clip box", &e.box_enabled);
  if (e.box_enabled) {
    // Steps of 1/200 of the cloud's extent per pixel dragged: fine enough for a building in a
    // city, quick enough to sweep the cloud.
    const auto size = s.extent.bounds.size();
    const double step = std::max({size[0], size[1], size[2], 1e-6}) / 200.0;
    changed |= ImGui::DragScalarN("min", ImGuiDataType_Double, e.box.min.data(), 3, float(step),
                                  nullptr, nullptr, "%.3f");
    changed |= ImGui::DragScalarN("max", ImGuiDataType_Double, e.box.max.data(), 3, float(step),
                                  nullptr, nullptr, "%.3f");
    if (ImGui::RadioButton("inside", !e.box_outside)) {
      e.box_outside = false;
      changed = true;
    }
    ImGui::SameLine();
    if (ImGui::RadioButton("outside", e.box_outside)) {
      e.box_outside = true;
      changed = true;
    }
    if (ImGui::Button("reset to the cloud's bounds")) {
      e.box = s.extent.bounds;
      changed = true;
    }
  }
  if (!changed) return;
  // Dragged past each other, min and max swap roles rather than emptying the box.
  Bounds3 box = e.box;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (box.min[axis] > box.max[axis]) std::swap(box.min[axis], box.max[axis]);
  }
  if (e.box_enabled) {
    s.settings.filter.setClipBox(box, e.box_outside);
  } else {
    s.settings.filter.clip_planes.clear();
    s.settings.filter.clip_outside = false;
  }
}

}  // namespace

void prepareFilters(Session& s, const PointCloud* points, bool whole, bool has_classification,
                    bool first) {
  Session::FilterEditor& e = s.filter_editor;
  e.classified = has_classification;
  e.listed = {};
  setBit(e.listed, 0);  // what a cloud without classification is
  if (has_classification) {
    if (!whole) {
      for (int c = 0; c < 19; ++c) {
        if (!asprsClassName(c).empty()) setBit(e.listed, c);
      }
    }
    if (points && points->hasClassification()) {
      for (const std::uint8_t c : points->classification) setBit(e.listed, c);
    }
  }
  // The command line's box for the first cloud; any other starts as the cloud's bounds, off.
  const std::optional<Bounds3> given = s.options->settings.filter.clipBox();
  if (first && given) {
    e.box_enabled = true;
    e.box = *given;
    e.box_outside = s.options->settings.filter.clip_outside;
    return;
  }
  e.box_enabled = e.box_outside = false;
  e.box = s.extent.bounds;
  s.settings.filter.clip_planes.clear();
  s.settings.filter.clip_outside = false;
}

void drawFilterPanel(Session& s) {
  ImGui::Separator();
  ImGui::TextDisabled("Filters");
  if (ImGui::TreeNode("classes")) {
    drawClassCheckboxes(s);
    ImGui::TreePop();
  }
  drawClipBoxEditor(s);
}

}  // namespace parallax::viewer_internal
