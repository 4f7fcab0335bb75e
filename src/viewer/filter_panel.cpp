// The viewer panel's "Filters" section: which classes are drawn (with the classification colour
// mode's legend), which returns, ranges of intensity, elevation and GPS time (sliders over the
// data's ranges), a clip box and the command line's clip polygon. Everything here edits
// RenderSettings::filter, which the rasterizers read as uniforms: a change redraws the picture
// (the settings differ from the drawn ones) and uploads nothing.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/classification.h"
#include "render/class_colors.h"
#include "render/overlay.h"
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

// The box as Potree and CloudCompare users handle one: moved by its centre, resized about it,
// turned about its vertical axis.
void drawClipBoxEditor(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  bool changed = ImGui::Checkbox("clip box", &e.box_enabled);
  if (e.box_enabled) {
    // Steps of 1/200 of the cloud's extent per pixel dragged: fine enough for a building in a
    // city, quick enough to sweep the cloud.
    const auto extent = s.extent.bounds.size();
    const double step = std::max({extent[0], extent[1], extent[2], 1e-6}) / 200.0;
    Bounds3& box = e.box.box;
    std::array<double, 3> centre{}, size{};
    for (std::size_t a = 0; a < 3; ++a) {
      centre[a] = 0.5 * (box.min[a] + box.max[a]);
      size[a] = box.max[a] - box.min[a];
    }
    const std::array<double, 3> was = centre;
    if (ImGui::DragScalarN("centre", ImGuiDataType_Double, centre.data(), 3, float(step), nullptr,
                           nullptr, "%.3f")) {
      for (std::size_t a = 0; a < 3; ++a) {
        box.min[a] += centre[a] - was[a];
        box.max[a] += centre[a] - was[a];
      }
      changed = true;
    }
    const double no_size = 0.0;
    if (ImGui::DragScalarN("size", ImGuiDataType_Double, size.data(), 3, float(step), &no_size,
                           nullptr, "%.3f")) {
      for (std::size_t a = 0; a < 3; ++a) {
        const double half = 0.5 * std::max(size[a], 0.0);
        box.min[a] = centre[a] - half;
        box.max[a] = centre[a] + half;
      }
      changed = true;
    }
    // Degrees, counter-clockwise seen from above, -180 to 180.
    float turn = float(e.box.yaw_degrees);
    if (ImGui::DragFloat("turn", &turn, 0.5f, -180.0f, 180.0f, "%.1f deg")) {
      e.box.yaw_degrees = double(turn);
      changed = true;
    }
    if (ImGui::Button("reset to the cloud's bounds")) {
      e.box = ClipBox{s.extent.bounds, 0.0};
      changed = true;
    }
  }
  if (!changed) return;
  if (e.box_enabled) {
    s.settings.filter.setClipBox(e.box.box, e.box_outside, e.box.yaw_degrees);
  } else {
    s.settings.filter.clip_planes.clear();
  }
}

// Inside / outside / highlight of the region (box and polygon alike, as --clip-mode).
void drawClipMode(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  if (!e.box_enabled && !e.polygon_enabled) return;
  if (ImGui::RadioButton("inside", !e.box_outside && !e.highlight)) {
    e.box_outside = e.highlight = false;
  }
  ImGui::SameLine();
  if (ImGui::RadioButton("outside", e.box_outside && !e.highlight)) {
    e.box_outside = true, e.highlight = false;
  }
  ImGui::SameLine();
  if (ImGui::RadioButton("highlight", e.highlight)) e.highlight = true;
  s.settings.filter.clip_outside = e.box_outside && !e.highlight;
  s.settings.filter.clip_highlight = e.highlight;
}

constexpr std::array<const char*, 5> kReturnKindNames{"first", "last", "intermediate", "single",
                                                      "multiple"};

void applyReturns(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  PointFilter& filter = s.settings.filter;
  if (!e.returns_enabled) {
    filter.returns.fill(~0u);
    return;
  }
  std::vector<ReturnKind> kinds;
  std::vector<int> numbers;
  for (std::size_t k = 0; k < e.return_kinds.size(); ++k) {
    if (e.return_kinds[k]) kinds.push_back(ReturnKind(k));
  }
  for (int r = 0; r < 16; ++r) {
    if ((e.return_numbers >> r) & 1u) numbers.push_back(r);
  }
  filter.keepOnlyReturns(kinds, numbers);
}

void drawReturns(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  bool changed = ImGui::Checkbox("returns", &e.returns_enabled);
  if (e.returns_enabled) {
    ImGui::TextDisabled("keep any of (no returns: return 1 of 1)");
    for (std::size_t k = 0; k < kReturnKindNames.size(); ++k) {
      if (k) ImGui::SameLine();
      changed |= ImGui::Checkbox(kReturnKindNames[k], &e.return_kinds[k]);
    }
    for (int r = 1; r <= 7; ++r) {
      if (r > 1) ImGui::SameLine();
      bool on = (e.return_numbers >> r) & 1u;
      const std::string label = std::to_string(r);
      if (ImGui::Checkbox(label.c_str(), &on)) {
        e.return_numbers = on ? e.return_numbers | 1u << r : e.return_numbers & ~(1u << r);
        changed = true;
      }
    }
  }
  if (changed) applyReturns(s);
}

// A range slider pair over the data's range; `target` is set while enabled.
void drawRange(const char* label, Session::FilterEditor::Range& range,
               std::optional<ValueRange>& target, const char* format) {
  bool changed = ImGui::Checkbox(label, &range.enabled);
  if (range.enabled) {
    ImGui::PushID(label);
    // Sliders over the data's range; Ctrl + click types a value beyond it.
    changed |= ImGui::SliderScalarN("##range", ImGuiDataType_Double, &range.value.min, 2,
                                    &range.data.min, &range.data.max, format);
    ImGui::SameLine();
    if (ImGui::Button("all")) {
      range.value = range.data;
      changed = true;
    }
    ImGui::PopID();
  }
  if (!changed) return;
  ValueRange value = range.value;
  if (value.min > value.max) std::swap(value.min, value.max);
  target = range.enabled ? std::optional<ValueRange>(value) : std::nullopt;
}

void drawPolygon(Session& s) {
  Session::FilterEditor& e = s.filter_editor;
  if (e.polygon.empty()) return;
  const std::string label = "clip polygon (" + std::to_string(e.polygon.size()) + " vertices)";
  if (!ImGui::Checkbox(label.c_str(), &e.polygon_enabled)) return;
  s.settings.filter.polygon = e.polygon_enabled ? e.polygon : std::vector<std::array<double, 2>>{};
}

// The range of a scalar column, or {0, 0} without it.
ValueRange columnRange(const ScalarColumn* column, std::uint64_t count) {
  if (!column || count == 0) return {};
  ValueRange range{INFINITY, -INFINITY};
  for (std::uint64_t i = 0; i < count; ++i) {
    const double v = column->valueAsDouble(i);
    range.min = std::min(range.min, v), range.max = std::max(range.max, v);
  }
  return range;
}

// Starts a range editor: the command line's range for the first cloud, else off; the sliders
// span the data's range (and the command line's).
void prepareRange(Session::FilterEditor::Range& range, ValueRange data,
                  const std::optional<ValueRange>& given, std::optional<ValueRange>& target,
                  bool first) {
  range.data = data;
  range.enabled = first && given;
  range.value = range.enabled ? *given : data;
  if (range.enabled) {
    range.data.min = std::min(range.data.min, given->min);
    range.data.max = std::max(range.data.max, given->max);
  }
  target = range.enabled ? given : std::nullopt;
}

}  // namespace

namespace {

// The data's range is now `data` (a column read after the cloud opened): the sliders span it,
// and a range still at the old data's (untouched, or enabled before the column was there) takes
// the new one.
void widenRange(Session::FilterEditor::Range& range, ValueRange data,
                std::optional<ValueRange>& target) {
  if (data == range.data) return;
  if (range.value == range.data) range.value = data;
  range.data = data;
  if (range.enabled) {
    ValueRange value = range.value;
    if (value.min > value.max) std::swap(value.min, value.max);
    target = value;
  }
}

}  // namespace

void updateFilterRanges(Session& s) {
  if (!s.cloud_points || s.cloud_points->count == 0) return;
  const PointCloud& points = *s.cloud_points;
  Session::FilterEditor& e = s.filter_editor;
  if (points.hasIntensity()) {
    const auto [lo, hi] = std::minmax_element(points.intensity.begin(), points.intensity.end());
    widenRange(e.intensity, {double(*lo), double(*hi)}, s.settings.filter.intensity);
  }
  if (const ScalarColumn* gps = points.findScalar(filter_names::kGpsTime)) {
    widenRange(e.gps_time, columnRange(gps, points.count), s.settings.filter.gps_time);
  }
}

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
  // Ranges over the data: the whole cloud's or the preview's; an octree's as its format records
  // them (OctreeInfo), else intensity over 16 bits and GPS time unknown (Ctrl + click to type).
  const PointFilter& options = s.options->settings.filter;
  PointFilter& filter = s.settings.filter;
  ValueRange intensity{0.0, s.octree && s.octree->info().has_intensity ? 65535.0 : 0.0};
  ValueRange gps_time{};
  if (points) {
    if (points->hasIntensity() && points->count > 0) {
      const auto [lo, hi] = std::minmax_element(points->intensity.begin(), points->intensity.end());
      intensity = {double(*lo), double(*hi)};
    }
    gps_time = columnRange(points->findScalar(filter_names::kGpsTime), points->count);
  } else if (s.octree) {
    const OctreeInfo& info = s.octree->info();
    if (info.intensity_range) intensity = {(*info.intensity_range)[0], (*info.intensity_range)[1]};
    if (info.gps_time_range) gps_time = {(*info.gps_time_range)[0], (*info.gps_time_range)[1]};
  }
  prepareRange(e.intensity, intensity, options.intensity, filter.intensity, first);
  prepareRange(e.elevation, {s.extent.bounds.min[2], s.extent.bounds.max[2]}, options.elevation,
               filter.elevation, first);
  prepareRange(e.gps_time, gps_time, options.gps_time, filter.gps_time, first);
  // The command line's returns table stays for the first cloud until the checkboxes are used.
  e.returns_enabled = false;
  if (!first) filter.returns.fill(~0u);
  e.polygon = options.polygon;
  e.polygon_enabled = first && !options.polygon.empty();
  if (!first) filter.polygon.clear();

  // The command line's box for the first cloud; any other starts as the cloud's bounds, off.
  const std::optional<ClipBox> given = s.options->settings.filter.clipBox();
  if (first && given) {
    e.box_enabled = true;
    e.box = *given;
    e.box_outside = s.options->settings.filter.clip_outside;
    e.highlight = s.options->settings.filter.clip_highlight;
    return;
  }
  e.box_enabled = false;
  e.box_outside = e.polygon_enabled && options.clip_outside;
  e.highlight = e.polygon_enabled && options.clip_highlight;
  s.settings.filter.clip_highlight = e.highlight;
  e.box = ClipBox{s.extent.bounds, 0.0};
  s.settings.filter.clip_planes.clear();
  s.settings.filter.clip_outside = e.box_outside;
}

void appendClipBoxOutline(const Session& s, OverlayScene& scene) {
  const Session::FilterEditor& e = s.filter_editor;
  if (!e.box_enabled || !s.show_panel) return;
  const Bounds3& box = e.box.box;
  const auto corners = e.box.corners();
  const OverlayColor orange{1.0f, 0.6f, 0.1f, 1.0f};  // the highlight mode's tint
  for (const double z : {box.min[2], box.max[2]}) {
    OverlayPolyline ring;
    ring.closed = true, ring.color = orange, ring.width_px = 1.5f;
    for (const auto& c : corners) ring.points.emplace_back(c[0], c[1], z);
    scene.polylines.push_back(std::move(ring));
  }
  for (const auto& c : corners) {
    OverlayPolyline edge;
    edge.color = orange, edge.width_px = 1.5f;
    edge.points = {{c[0], c[1], box.min[2]}, {c[0], c[1], box.max[2]}};
    scene.polylines.push_back(std::move(edge));
  }
}

void drawFilterPanel(Session& s) {
  ImGui::Separator();
  ImGui::TextDisabled("Filters");
  // Open from the start for a classified cloud: its classes are what a surveyor looks at first.
  if (ImGui::TreeNodeEx("classes",
                        s.filter_editor.classified ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
    drawClassCheckboxes(s);
    ImGui::TreePop();
  }
  if (ImGui::TreeNode("returns and ranges")) {
    drawReturns(s);
    PointFilter& filter = s.settings.filter;
    drawRange("intensity", s.filter_editor.intensity, filter.intensity, "%.0f");
    drawRange("elevation", s.filter_editor.elevation, filter.elevation, "%.3f");
    drawRange("GPS time", s.filter_editor.gps_time, filter.gps_time, "%.6f");
    ImGui::TreePop();
  }
  drawClipBoxEditor(s);
  drawPolygon(s);
  drawClipMode(s);
}

}  // namespace parallax::viewer_internal
