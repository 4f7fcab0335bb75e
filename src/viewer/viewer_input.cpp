// The viewer's input: the GLFW key, scroll, mouse-button and drop callbacks, the held keys a
// frame reads, and the settings keys change (stereo mode and separation, rasterizer).
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "render/stereo.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

// Quad-buffer only where the window has a stereo visual; elsewhere sbs, and the user is told.
void setStereoMode(Session& s, StereoMode mode) {
  if (mode == StereoMode::QuadBuffer && !s.quad_buffer) {
    s.status =
        "quad-buffer stereo: this display offers no stereo (GL_STEREO) visual; showing sbs (side "
        "by side) instead";
    mode = StereoMode::SideBySide;
  } else {
    s.status = "stereo " + std::string(stereoModeName(mode));
  }
  s.stereo.mode = mode;
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

void setRasterizer(Session& s, RasterizerKind kind) {
  s.settings.rasterizer = kind;
  int width = 1, height = 1;
  glfwGetFramebufferSize(s.window, &width, &height);
  const Composition composition =
      stereoFrame(s.camera, s.stereo, std::max(width, 1), std::max(height, 1)).composition;
  std::string reason;
  const RasterizerKind drawing =
      s.renderer->chooseRasterizer(s.settings, width, height, composition, &reason);
  s.status =
      "rasterizer " + std::string(rasterizerKindName(kind)) + ": " +
      (drawing == RasterizerKind::Compute ? "the compute rasterizer draws" : "GL_POINTS draws") +
      (reason.empty() ? "" : " (" + reason + ")");
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

void cycleStereoMode(Session& s) {
  const auto& modes = allStereoModes();
  auto next = std::find(modes.begin(), modes.end(), s.stereo.mode) + 1;
  if (next != modes.end() && *next == StereoMode::QuadBuffer && !s.quad_buffer) ++next;
  setStereoMode(s, next == modes.end() ? modes.front() : *next);
}

// Scales the eye separation or the convergence distance, automatic values first made explicit.
void scaleStereo(Session& s, double separation_factor, double convergence_factor) {
  const StereoSettings resolved = resolvedStereo(s.stereo, s.camera);
  s.stereo.eye_separation = resolved.eye_separation * separation_factor;
  s.stereo.convergence = resolved.convergence * convergence_factor;
  char text[160];
  std::snprintf(text, sizeof text, "stereo eye separation %.4g, convergence %.4g",
                s.stereo.eye_separation, s.stereo.convergence);
  s.status = text;
  std::fprintf(stderr, "parallax view: %s\n", text);
}

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
  Session& s = sessionOf(window);
  if (s.trace_keys && action == GLFW_PRESS) s.keys_this_frame.push_back(key);
  if ((action != GLFW_PRESS && action != GLFW_REPEAT) || ImGui::GetIO().WantCaptureKeyboard) return;
  // Held keys repeat only for the stereo adjustments.
  const bool adjust = key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET ||
                      key == GLFW_KEY_MINUS || key == GLFW_KEY_EQUAL;
  if (action == GLFW_REPEAT && !adjust) return;
  if (registrationKey(s, key, mods)) return;
  if (measureKey(s, key, mods)) return;
  switch (key) {
    case GLFW_KEY_3:
      cycleStereoMode(s);
      break;
    case GLFW_KEY_LEFT_BRACKET:
      scaleStereo(s, 1.0 / 1.1, 1.0);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      scaleStereo(s, 1.1, 1.0);
      break;
    case GLFW_KEY_MINUS:
      scaleStereo(s, 1.0, 1.0 / 1.1);
      break;
    case GLFW_KEY_EQUAL:
      scaleStereo(s, 1.0, 1.1);
      break;
    case GLFW_KEY_R: {
      const RasterizerKind next =
          s.settings.rasterizer == RasterizerKind::Auto      ? RasterizerKind::Compute
          : s.settings.rasterizer == RasterizerKind::Compute ? RasterizerKind::Points
                                                             : RasterizerKind::Auto;
      setRasterizer(s, next);
      break;
    }
    case GLFW_KEY_C: {
      // The panel's colour list, in its order; a mode chosen shows the cloud's own colours again.
      constexpr std::array kModes{
          ColorMode::Rgb,    ColorMode::Elevation,      ColorMode::Intensity,
          ColorMode::Normal, ColorMode::Classification, ColorMode::Uniform};
      const auto at = std::find(kModes.begin(), kModes.end(), s.settings.color);
      s.settings.color = at == kModes.end() || at + 1 == kModes.end() ? kModes.front() : *(at + 1);
      s.settings.scalar.field.clear();
      s.status = "colour " + std::string(colorModeName(s.settings.color));
      std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
      break;
    }
    case GLFW_KEY_K:
      s.process.run_requested = true;
      break;
    case GLFW_KEY_X:
      s.stereo.swap_eyes = !s.stereo.swap_eyes;
      s.status = s.stereo.swap_eyes ? "stereo eyes swapped" : "stereo eyes not swapped";
      break;
    case GLFW_KEY_COMMA:
    case GLFW_KEY_PERIOD: {
      std::uint64_t& budget = s.lod_settings.selection.point_budget;
      budget = key == GLFW_KEY_COMMA ? std::max<std::uint64_t>(budget / 2, 1) : budget * 2;
      s.status = "point budget " + std::to_string(budget);
      std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
      break;
    }
    case GLFW_KEY_ESCAPE:
      // What is open closes first (the help, a list opened in the panel); only then Esc quits.
      if (s.show_help) {
        s.show_help = false;
      } else if (ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) {
        s.close_popups = true;
      } else {
        glfwSetWindowShouldClose(window, GLFW_TRUE);
      }
      break;
    case GLFW_KEY_H:
      s.show_help = !s.show_help;
      break;
    case GLFW_KEY_G:
      s.show_panel = !s.show_panel;
      break;
    case GLFW_KEY_F:
      fitCamera(s);
      break;
    case GLFW_KEY_TAB:
      s.controller.fly = !s.controller.fly;
      s.status = s.controller.fly ? "fly mode on (W A S D, Q E; Tab: orbit again)" : "fly mode off";
      std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
      break;
    case GLFW_KEY_P:
      s.screenshot_requested = true;
      s.screenshot_with_panel = (mods & GLFW_MOD_SHIFT) != 0;
      break;
    case GLFW_KEY_V:
      s.vsync = !s.vsync;
      glfwSwapInterval(s.vsync ? 1 : 0);
      break;
    case GLFW_KEY_O:
      s.camera.projection = s.camera.projection == Projection::Perspective
                                ? Projection::Orthographic
                                : Projection::Perspective;
      break;
    case GLFW_KEY_T:
      s.controller.orbit_mode =
          s.controller.orbit_mode == OrbitMode::Turntable ? OrbitMode::Free : OrbitMode::Turntable;
      break;
    default:
      break;
  }
}

void onScroll(GLFWwindow* window, double, double y) {
  if (ImGui::GetIO().WantCaptureMouse) return;
  sessionOf(window).scroll_steps += y;
}

void onMouseButton(GLFWwindow* window, int button, int action, int mods) {
  if (ImGui::GetIO().WantCaptureMouse || button != GLFW_MOUSE_BUTTON_LEFT) return;
  Session& s = sessionOf(window);
  MeasureSession& measure = s.measure;
  if ((measure.tool != MeasureTool::None || pairPickingTakesClicks(s)) &&
      !(mods & GLFW_MOD_CONTROL)) {
    // With a tool (or while picking registration pairs), a click (press and release within a
    // few pixels) adds a point; a drag still orbits. No double-click pivot meanwhile: two quick
    // clicks are two points.
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    if (action == GLFW_PRESS) {
      measure.press_valid = true;
      measure.press_x = x, measure.press_y = y;
    } else if (action == GLFW_RELEASE && measure.press_valid) {
      measure.press_valid = false;
      if (std::hypot(x - measure.press_x, y - measure.press_y) <= 4.0) {
        measure.click_requested = true;
        measure.click_x = x, measure.click_y = y;
      }
    }
    return;
  }
  if (action != GLFW_PRESS) return;
  if (mods & GLFW_MOD_CONTROL) {
    s.point_pick_requested = true;  // not also half of a double-click
    return;
  }
  const double now = glfwGetTime();
  if (now - s.last_click_time < 0.35) s.pick_requested = true;
  s.last_click_time = now;
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
  Session& s = sessionOf(window);
  if (count > 0) s.dropped.emplace_back(paths[0]);  // one cloud at a time: the first file
}

InputState readInput(GLFWwindow* window) {
  InputState input;
  glfwGetCursorPos(window, &input.cursor_x, &input.cursor_y);
  const ImGuiIO& io = ImGui::GetIO();
  auto key = [&](int k) { return !io.WantCaptureKeyboard && glfwGetKey(window, k) == GLFW_PRESS; };
  auto button = [&](int b) {
    return !io.WantCaptureMouse && glfwGetMouseButton(window, b) == GLFW_PRESS;
  };
  input.left = button(GLFW_MOUSE_BUTTON_LEFT);
  input.right = button(GLFW_MOUSE_BUTTON_RIGHT);
  input.middle = button(GLFW_MOUSE_BUTTON_MIDDLE);
  input.shift = key(GLFW_KEY_LEFT_SHIFT) || key(GLFW_KEY_RIGHT_SHIFT);
  input.forward = key(GLFW_KEY_W), input.back = key(GLFW_KEY_S);
  input.left_key = key(GLFW_KEY_A), input.right_key = key(GLFW_KEY_D);
  input.down = key(GLFW_KEY_Q), input.up = key(GLFW_KEY_E);
  return input;
}

}  // namespace parallax::viewer_internal
