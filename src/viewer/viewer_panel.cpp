// The viewer's on-screen panel (Dear ImGui) and its help window.
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include "lod/potree_reader.h"
#include "net/network_counters.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

const char* const kHelp =
    "Mouse\n"
    "  left drag          orbit around the pivot\n"
    "  right/middle drag  pan (or shift + left drag)\n"
    "  wheel              zoom to the cursor\n"
    "  double-click       new pivot at the point under the cursor\n"
    "  ctrl + click       pick the point under the cursor (or the nearest within 3 pixels):\n"
    "                     its coordinates and attributes in the panel and on stderr\n"
    "  click              with a measurement tool (panel: Measure): add the point under the\n"
    "                     cursor; Enter finishes, Backspace removes the last, Esc cancels,\n"
    "                     Delete removes the selected measurement, Ctrl + E reopens it;\n"
    "                     Ctrl + S saves the measurements; Ctrl + X exports the selected\n"
    "                     profile as CSV (with shift: LAS); Ctrl + V computes the volume\n"
    "                     inside the selected area (panel: Measure, Volume)\n"
    "  click              while picking point pairs (panel: Registration): a point of the\n"
    "                     source, then its match on the target; Backspace takes the last\n"
    "                     back; Enter refines the pairs' transform by ICP\n"
    "Keys\n"
    "  H      this help\n"
    "  G      show or hide the panel\n"
    "  F      fit the cloud in view\n"
    "  Tab    fly mode (W A S D, Q E down/up, shift faster; drag to look); the keys go to\n"
    "         the 3D view, except while a field of the panel is being edited\n"
    "  O      perspective / orthographic\n"
    "  T      turntable / free orbit\n"
    "  V      vsync on / off\n"
    "  P      screenshot of the picture (PNG, without the panel; path on stderr and in\n"
    "         the panel); shift + P: the window as seen, panel included\n"
    "  3      stereo mode: mono, sbs, sbs-squeezed, tb, anaglyph, ... (cycles)\n"
    "  [ ]    stereo eye separation smaller / larger\n"
    "  - =    stereo convergence nearer / farther\n"
    "  X      swap the eyes\n"
    "  , .    point budget halved / doubled (level of detail)\n"
    "  R      rasterizer: auto, compute, points (cycles)\n"
    "  C      colour: rgb, elevation, intensity, normal, classification, uniform (cycles)\n"
    "  K      run the Processing panel's steps on the cloud shown\n"
    "  Ctrl+T accept the registration shown: write its transform (panel: Registration)\n"
    "  Esc    close this help or an open list; cancel a measurement being drawn;\n"
    "         otherwise quit\n"
    "Drop a point file or a Potree directory on the window to open it; `parallax view URL`\n"
    "streams a Potree directory from a web server.";

// Wide enough for the widest label beside its field ("eye separation ([ ])") and a usable field.
constexpr float kPanelWidth = 400.0f;
constexpr const char* kWidestLabel = "eye separation ([ ])";
const ImVec4 kErrorColor(1.0f, 0.35f, 0.35f, 1.0f);

template <class Enum, std::size_t N>
bool comboOf(const char* label, Enum& value, const std::array<Enum, N>& values,
             std::string_view (*name)(Enum)) {
  bool changed = false;
  if (ImGui::BeginCombo(label, std::string(name(value)).c_str())) {
    for (Enum option : values) {
      if (ImGui::Selectable(std::string(name(option)).c_str(), option == value)) {
        value = option;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

// A scalar attribute's colours, as CloudCompare's scalar-field display: the attribute (any the
// whole cloud shown has), the ramp, and the range (the attribute's own until one is typed).
// The legend of a scalar colouring: the ramp from the range's minimum (left) to its maximum
// (right), the two values under its ends.
void drawRampLegend(ColorRamp ramp, const ScalarRange& range) {
  const float width = ImGui::CalcItemWidth();
  const float height = ImGui::GetFrameHeight() * 0.6f;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  constexpr int kSteps = 64;  // linear pieces: the ramps are piecewise linear in fewer
  const auto color = [&](int i) {
    const Rgba8 c = rampColor(ramp, double(i) / kSteps);
    return IM_COL32(c.r, c.g, c.b, 255);
  };
  for (int i = 0; i < kSteps; ++i) {
    const float x0 = origin.x + width * float(i) / kSteps;
    const float x1 = origin.x + width * float(i + 1) / kSteps;
    draw->AddRectFilledMultiColor(ImVec2(x0, origin.y), ImVec2(x1, origin.y + height), color(i),
                                  color(i + 1), color(i + 1), color(i));
  }
  ImGui::Dummy(ImVec2(width, height));
  char low[32], high[32];
  std::snprintf(low, sizeof low, "%.6g", range.min);
  std::snprintf(high, sizeof high, "%.6g", range.max);
  ImGui::TextUnformatted(low);
  ImGui::SameLine(std::max(ImGui::GetCursorPosX(), width - ImGui::CalcTextSize(high).x));
  ImGui::TextUnformatted(high);
}

void drawScalarFieldPanel(Session& s) {
  if (!s.cloud || !s.cloud_points) return;  // octrees carry no scalar attributes to the renderer
  const std::vector<std::string> fields = cloudScalarFields(s);
  if (fields.empty()) return;
  ScalarColoring& scalar = s.settings.scalar;
  const std::string current = scalar.field.empty() ? "(none)" : scalar.field;
  if (ImGui::BeginCombo("scalar field", current.c_str())) {
    if (ImGui::Selectable("(none)", scalar.field.empty())) scalar.field.clear();
    for (const auto& field : fields) {
      if (ImGui::Selectable(field.c_str(), field == scalar.field)) {
        scalar.field = field;
        scalar.range.reset();  // a new attribute starts at its own range
        s.settings.color = ColorMode::Rgb;
      }
    }
    ImGui::EndCombo();
  }
  if (!s.scalar_error.empty()) ImGui::TextWrapped("%s", s.scalar_error.c_str());
  if (scalar.field.empty()) return;
  comboOf("ramp", scalar.ramp,
          std::array{ColorRamp::Viridis, ColorRamp::Rainbow, ColorRamp::Grey, ColorRamp::CoolWarm},
          colorRampName);
  // Edited as a pair; only a range with min below max is applied.
  ScalarRange shown = scalar.range.value_or(s.shown_scalar_range);
  double bounds[2] = {shown.min, shown.max};
  if (ImGui::InputScalarN("range", ImGuiDataType_Double, bounds, 2, nullptr, nullptr, "%.6g",
                          ImGuiInputTextFlags_EnterReturnsTrue) &&
      bounds[0] < bounds[1]) {
    scalar.range = ScalarRange{bounds[0], bounds[1]};
  }
  ImGui::SameLine();
  if (ImGui::Button("auto")) scalar.range.reset();
  // The automatic range's percentiles (a diverging ramp's is then centred on zero).
  double percentiles[2] = {scalar.percentiles.low, scalar.percentiles.high};
  if (ImGui::InputScalarN("auto percentiles", ImGuiDataType_Double, percentiles, 2, nullptr,
                          nullptr, "%.3g", ImGuiInputTextFlags_EnterReturnsTrue) &&
      percentiles[0] >= 0.0 && percentiles[0] < percentiles[1] && percentiles[1] <= 100.0) {
    scalar.percentiles = {percentiles[0], percentiles[1]};
    scalar.range.reset();
  }
  ImGui::Checkbox("legend in the window", &s.show_legend);
  drawRampLegend(scalar.ramp, shown);
}

// The level-of-detail part of the panel: budget, what the last update selected and drew, and the
// background build's progress.
void drawLodPanel(Session& s) {
  ImGui::Separator();
  ImGui::TextDisabled("Level of detail");
  NodeSelectionSettings& selection = s.lod_settings.selection;
  const std::uint64_t low = 1000, high = 1'000'000'000;
  if (ImGui::SliderScalar("point budget (, .)", ImGuiDataType_U64, &selection.point_budget, &low,
                          &high, "%llu", ImGuiSliderFlags_Logarithmic)) {
    selection.point_budget = std::max<std::uint64_t>(selection.point_budget, 1);
  }
  float min_size = float(selection.min_node_size_px);
  if (ImGui::SliderFloat("min node size", &min_size, 0.0f, 200.0f, "%.0f px")) {
    selection.min_node_size_px = min_size;
  }
  // Progressive refinement: a moving camera draws what fits the frame budget, a still one
  // completes the picture.
  bool progressive = s.frame_budget_ms > 0;
  if (ImGui::Checkbox("progressive refinement", &progressive)) {
    s.frame_budget_ms = progressive ? std::max(s.options->frame_budget_ms, 1000.0 / 15.0) : 0.0;
  }
  if (progressive) {
    float budget_ms = float(s.frame_budget_ms);
    if (ImGui::SliderFloat("frame budget", &budget_ms, 5.0f, 500.0f, "%.0f ms",
                           ImGuiSliderFlags_Logarithmic)) {
      s.frame_budget_ms = std::max(budget_ms, 1.0f);
    }
    if (s.lod) {
      ImGui::Text("picture %s, %d part%s, %.1f M points/s",
                  s.progressive.complete() ? "complete" : "refining", s.picture_parts,
                  s.picture_parts == 1 ? "" : "s", s.progressive.pointsPerSecond() / 1e6);
    }
  }
  if (s.lod) {
    const LodStats& l = s.lod_stats;
    ImGui::Text("selected %zu nodes, %llu points", l.selected_nodes,
                static_cast<unsigned long long>(l.selected_points));
    ImGui::Text("drawn %zu nodes, %llu points", l.drawn_nodes,
                static_cast<unsigned long long>(l.drawn_points));
    ImGui::Text("resident %zu nodes, GPU %.1f MB", l.resident_nodes, double(l.gpu_bytes) / 1e6);
    ImGui::Text("pending loads %zu%s", l.pending_loads, s.lod->complete() ? ", complete" : "");
    if (l.failed_nodes)
      ImGui::TextWrapped("%zu nodes failed: %s", l.failed_nodes, s.lod->firstError().c_str());
  }
  if (s.build) {
    const BackgroundOctreeBuild::Status status = s.build->status();
    ImGui::Text("building the octree: %s", status.stage.c_str());
    const float fraction = status.total ? float(double(status.done) / double(status.total)) : 0.0f;
    ImGui::ProgressBar(std::min(fraction, 1.0f));
  }
}

// Who draws points: the choice (R), who drew the last frame and, where the compute rasterizer
// was asked for but GL_POINTS drew, why.
void drawRasterizerPanel(Session& s, const FrameStats& stats) {
  RasterizerKind kind = s.settings.rasterizer;
  if (comboOf("rasterizer (R)", kind,
              std::array{RasterizerKind::Auto, RasterizerKind::Compute, RasterizerKind::Points},
              rasterizerKindName)) {
    setRasterizer(s, kind);
  }
  ImGui::Text("drawn by %s",
              stats.rasterizer == RasterizerKind::Compute ? "the compute rasterizer" : "GL_POINTS");
  if (!stats.fallback_reason.empty()) ImGui::TextWrapped("(%s)", stats.fallback_reason.c_str());
  if (s.settings.rasterizer != RasterizerKind::Points) ImGui::Checkbox("HQ splats", &s.settings.hq);
}

// The network part, for an octree read over HTTP (or being opened): requests in flight, the
// rate of received bytes, reads served by the disk cache, retries and nodes that failed.
void drawNetworkPanel(Session& s) {
  const std::optional<PotreeReadStats> read = s.octree ? potreeReadStats(*s.octree) : std::nullopt;
  if (!s.opening && !(read && read->remote)) return;
  ImGui::Separator();
  ImGui::TextDisabled("Network");
  if (s.opening) ImGui::TextWrapped("opening %s", s.opening->url.c_str());
  const NetworkStats net = networkStats();
  ImGui::Text("requests in flight %llu (of %llu)",
              static_cast<unsigned long long>(net.requests_in_flight),
              static_cast<unsigned long long>(net.requests));
  ImGui::Text("received %.1f MB, %.2f MB/s", double(net.bytes_received) / 1e6,
              net.bytes_per_second / 1e6);
  ImGui::Text("cache hits %llu (%.1f MB), retries %llu, cancelled %llu",
              static_cast<unsigned long long>(net.cache_hits), double(net.cache_bytes) / 1e6,
              static_cast<unsigned long long>(net.retries),
              static_cast<unsigned long long>(net.cancelled));
  const std::size_t failed = s.lod ? s.lod_stats.failed_nodes : 0;
  if (failed) {
    ImGui::TextWrapped("failed nodes %zu: %s", failed, s.lod->firstError().c_str());
  } else {
    ImGui::Text("failed nodes 0");
  }
}

// The last Ctrl + click's point: the source's coordinates and every attribute.
void drawPickedPanel(const Session& s) {
  if (!s.picked) return;
  ImGui::Separator();
  ImGui::TextDisabled("Picked point (ctrl + click)");
  if (s.stereo.mode != StereoMode::Mono) {
    ImGui::Text("%s eye", s.picked->view == 0 ? "left" : "right");
  }
  for (const PointAttribute& attribute : s.picked->attributes) {
    ImGui::Text("%-16s %s", attribute.name.c_str(), formatAttributeValue(attribute.value).c_str());
  }
}

}  // namespace

float panelWidth() {
  return kPanelWidth;
}

bool panelStartsCollapsed(const Session& s) {
  const StereoMode mode = s.stereo.mode;
  return mode == StereoMode::SideBySide || mode == StereoMode::SideBySideSqueezed ||
         mode == StereoMode::TopBottom;
}

void drawPanel(Session& s, const FrameStats& stats) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(panelStartsCollapsed(s), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, 0), ImGuiCond_FirstUseEver);
  // The keyboard belongs to the 3D view (Tab, WASD, 3, H...) until a field is clicked: the panel
  // takes no focus when it appears and none of its fields is a Tab stop.
  if (!ImGui::Begin("Parallax", nullptr, ImGuiWindowFlags_NoFocusOnAppearing)) {
    s.panel_right = 0.0f;  // collapsed: a title bar only
    ImGui::End();
    return;
  }
  s.panel_right = ImGui::GetWindowPos().x + ImGui::GetWindowSize().x;
  ImGui::PushAllowKeyboardFocus(false);
  // Every label in full beside its field (fields take what the labels leave).
  ImGui::PushItemWidth(
      -(ImGui::CalcTextSize(kWidestLabel).x + ImGui::GetStyle().ItemInnerSpacing.x));
  ImGui::TextWrapped(
      "%s", s.loaded_name.empty() ? "(no cloud: drop a file here)" : s.loaded_name.c_str());
  // The last failure to open and the Volume tool's error, first, where the eye is.
  if (!s.error.empty()) drawErrorText(s.error);
  if (const std::string* volume = volumeError(s)) drawErrorText("volume: " + *volume);
  // The picture shown: its points (every part of a refined one) and how long it took from the
  // start of its first part to the end of its last; then the frames of a moving camera.
  const std::uint64_t total =
      s.octree ? s.octree->info().point_count : (s.cloud ? s.cloud->pointCount() : 0);
  const bool refining = s.frame_budget_ms > 0 && s.picture_parts > 0 && !s.progressive.complete();
  ImGui::TextWrapped(
      "picture %llu points of %llu%s, drawn in %.1f ms%s",
      static_cast<unsigned long long>(s.picture_points), static_cast<unsigned long long>(total),
      refining ? " so far" : "", s.picture_seconds * 1e3,
      s.picture_parts > 1 ? (" (" + std::to_string(s.picture_parts) + " parts)").c_str() : "");
  const FrameTimeSummary moving = s.moving_frames.summary();
  if (moving.frames > 0) {
    ImGui::TextWrapped(
        "moving: %.1f FPS; frame median %.1f ms, p90 %.1f ms, worst %.1f ms (last %zu)",
        1.0 / std::max(moving.median_s, 1e-6), moving.median_s * 1e3, moving.p90_s * 1e3,
        moving.worst_s * 1e3, moving.frames);
  } else {
    ImGui::TextDisabled("moving: (frame times once the camera moves)");
  }
  ImGui::Text("GPU memory %.1f MB", (s.cloud ? double(s.cloud->gpuBytes()) / 1e6 : 0.0) +
                                        (s.lod ? double(s.lod_stats.gpu_bytes) / 1e6 : 0.0));
  if (ImGui::Checkbox("vsync (V)", &s.vsync)) glfwSwapInterval(s.vsync ? 1 : 0);
  drawRasterizerPanel(s, stats);
  drawLodPanel(s);
  drawNetworkPanel(s);

  RenderSettings& r = s.settings;
  ImGui::Separator();
  ImGui::TextDisabled("Points");
  if (comboOf("colour", r.color,
              std::array{ColorMode::Rgb, ColorMode::Elevation, ColorMode::Intensity,
                         ColorMode::Normal, ColorMode::Classification, ColorMode::Uniform},
              colorModeName)) {
    r.scalar.field.clear();  // a mode chosen: the cloud's own colours again
  }
  drawScalarFieldPanel(s);
  if (r.color == ColorMode::Uniform) ImGui::ColorEdit3("uniform colour", r.uniform_color.data());
  comboOf("size", r.size_mode,
          std::array{PointSizeMode::Fixed, PointSizeMode::Attenuated, PointSizeMode::Adaptive},
          pointSizeModeName);
  if (r.size_mode == PointSizeMode::Fixed) {
    ImGui::SliderFloat("pixels", &r.point_size_px, 1.0f, 32.0f, "%.0f");
  } else if (r.size_mode == PointSizeMode::Attenuated) {
    ImGui::DragFloat("world size", &r.world_size, r.world_size * 0.01f + 1e-6f, 0.0f, 1e6f, "%.4f");
  } else {
    ImGui::SliderFloat("x spacing", &r.adaptive_scale, 0.25f, 8.0f, "%.2f");
  }
  comboOf("shape", r.shape, std::array{PointShape::Square, PointShape::Round}, pointShapeName);
  ImGui::ColorEdit3("background", r.background.data());
  // Off keeps exact pixels; the renderer clamps the count to what the GPU offers.
  const int samples = r.samples > 1 ? r.samples : 0;
  const auto samples_label = [](int count) {
    return count > 1 ? std::to_string(count) + "x" : std::string("off");
  };
  if (ImGui::BeginCombo("multisampling", samples_label(samples).c_str())) {
    for (int count : {0, 2, 4, 8}) {
      if (ImGui::Selectable(samples_label(count).c_str(), count == samples)) r.samples = count;
    }
    ImGui::EndCombo();
  }
  ImGui::Separator();
  ImGui::TextDisabled("Shading");
  ImGui::Checkbox("lighting (needs normals)", &r.lighting);
  ImGui::Checkbox("eye-dome lighting", &r.edl);
  if (r.edl) {
    ImGui::SliderFloat("EDL strength", &r.edl_strength, 0.0f, 5.0f, "%.2f");
    ImGui::SliderFloat("EDL radius", &r.edl_radius_px, 1.0f, 4.0f, "%.1f px");
  }
  ImGui::Separator();
  ImGui::TextDisabled("Stereo");
  StereoMode mode = s.stereo.mode;
  if (comboOf("mode (3)", mode,
              std::array{StereoMode::Mono, StereoMode::SideBySide, StereoMode::SideBySideSqueezed,
                         StereoMode::TopBottom, StereoMode::Anaglyph, StereoMode::AnaglyphDubois,
                         StereoMode::Interlaced, StereoMode::QuadBuffer},
              stereoModeName)) {
    setStereoMode(s, mode);
  }
  if (s.stereo.mode != StereoMode::Mono) {
    // Shown resolved; editing makes the value explicit, "auto" returns to the default.
    const StereoSettings resolved = resolvedStereo(s.stereo, s.camera);
    float separation = float(resolved.eye_separation), convergence = float(resolved.convergence);
    if (ImGui::DragFloat("eye separation ([ ])", &separation, separation * 0.01f + 1e-6f, 0.0f,
                         1e9f, "%.4g")) {
      s.stereo.eye_separation = separation;
    }
    if (ImGui::DragFloat("convergence (- =)", &convergence, convergence * 0.01f + 1e-6f, 1e-6f,
                         1e9f, "%.4g")) {
      s.stereo.convergence = std::max(convergence, 1e-6f);
    }
    if (ImGui::Button("auto")) s.stereo.eye_separation = s.stereo.convergence = 0.0;
    ImGui::SameLine();
    ImGui::Checkbox("swap eyes (X)", &s.stereo.swap_eyes);
  }
  // Before the filters: what is added to the picture (the window tests scroll to the panel's end
  // to find the filters above the tools).
  drawRasterPanel(s);
  drawRegistrationPanel(s);
  drawFilterPanel(s);
  drawMeasurePanel(s);
  drawProcessPanel(s);
  drawPickedPanel(s);
  ImGui::Separator();
  ImGui::TextDisabled("Camera");
  bool ortho = s.camera.projection == Projection::Orthographic;
  if (ImGui::Checkbox("orthographic (O)", &ortho)) {
    s.camera.projection = ortho ? Projection::Orthographic : Projection::Perspective;
  }
  float fov = float(s.camera.fov_y_deg);
  if (ImGui::SliderFloat("field of view", &fov, 10.0f, 120.0f, "%.0f deg"))
    s.camera.fov_y_deg = fov;
  bool free_orbit = s.controller.orbit_mode == OrbitMode::Free;
  if (ImGui::Checkbox("free orbit (T)", &free_orbit)) {
    s.controller.orbit_mode = free_orbit ? OrbitMode::Free : OrbitMode::Turntable;
  }
  ImGui::Checkbox("fly mode (Tab)", &s.controller.fly);
  if (ImGui::Button("fit (F)")) fitCamera(s);
  ImGui::SameLine();
  if (ImGui::Button("save camera")) {
    const auto path = s.options->screenshot_dir / "camera.json";
    try {
      saveCamera(s.camera, path);
      s.status = "camera saved to " + path.string();
    } catch (const std::exception& e) {
      s.status = e.what();
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("screenshot (P)")) s.screenshot_requested = true;
  if (!s.status.empty()) ImGui::TextWrapped("%s", s.status.c_str());
  ImGui::TextDisabled("H: keys and mouse; drag the panel's edge to widen it");
  ImGui::PopItemWidth();
  ImGui::PopAllowKeyboardFocus();
  ImGui::End();
}

void drawErrorText(const std::string& text) {
  ImGui::PushStyleColor(ImGuiCol_Text, kErrorColor);
  ImGui::TextWrapped("%s", text.c_str());
  ImGui::PopStyleColor();
}

void drawErrorBanner(const Session& s) {
  const std::string* volume = volumeError(s);
  if ((s.error.empty() && !volume) || (s.show_panel && s.panel_right.value_or(0.0f) > 0.0f)) {
    return;
  }
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->Size.x * 0.5f, 10.0f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.0f));
  ImGui::Begin("##error", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs |
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoSavedSettings);
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + std::min(viewport->Size.x * 0.7f, 640.0f));
  ImGui::PushStyleColor(ImGuiCol_Text, kErrorColor);
  if (!s.error.empty()) ImGui::TextUnformatted(s.error.c_str());
  if (volume) ImGui::TextUnformatted(("volume: " + *volume).c_str());
  ImGui::PopStyleColor();
  ImGui::PopTextWrapPos();
  ImGui::End();
}

void drawEmptyWindowMessage(const Session& s) {
  // In the middle of the part of the window the panel leaves free.
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  const float left = s.show_panel ? s.panel_right.value_or(0.0f) : 0.0f;
  const float free_width = std::max(viewport->Size.x - left, viewport->Size.x * 0.3f);
  const float wrap = std::min(free_width * 0.85f, 520.0f);
  ImGui::SetNextWindowPos(ImVec2(viewport->Size.x - free_width * 0.5f, viewport->Size.y * 0.5f),
                          ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::Begin("##empty", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs |
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoSavedSettings);
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + wrap);
  if (s.opening) {
    ImGui::TextUnformatted(("opening " + s.opening->url).c_str());
  } else if (!s.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErrorColor);
    ImGui::TextUnformatted(s.error.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::TextUnformatted("Drop a point file or a Potree directory here (H: keys and mouse)");
  ImGui::PopTextWrapPos();
  ImGui::End();
}

void drawHelp() {
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->Size.x * 0.5f, viewport->Size.y * 0.5f),
                          ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("Keys", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::TextUnformatted(kHelp);
  ImGui::End();
}

}  // namespace parallax::viewer_internal
