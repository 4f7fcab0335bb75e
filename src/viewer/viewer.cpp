#include "viewer/viewer.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "io/point_file.h"
#include "render/gl_context.h"
#include "render/image_file.h"
#include "render/point_buffers.h"
#include "render/renderer.h"
#include "viewer/camera_controller.h"

namespace parallax {

namespace {

const char* const kHelp =
    "Mouse\n"
    "  left drag          orbit around the pivot\n"
    "  right/middle drag  pan (or shift + left drag)\n"
    "  wheel              zoom to the cursor\n"
    "  double-click       new pivot at the point under the cursor\n"
    "Keys\n"
    "  H      this help\n"
    "  G      show or hide the panel\n"
    "  F      fit the cloud in view\n"
    "  Tab    fly mode (W A S D, Q E down/up, shift faster; drag to look)\n"
    "  O      perspective / orthographic\n"
    "  T      turntable / free orbit\n"
    "  V      vsync on / off\n"
    "  P      screenshot (PNG, path shown in the panel)\n"
    "  3      stereo mode: mono, sbs, sbs-squeezed, tb, anaglyph, ... (cycles)\n"
    "  [ ]    stereo eye separation smaller / larger\n"
    "  - =    stereo convergence nearer / farther\n"
    "  X      swap the eyes\n"
    "  Esc    quit\n"
    "Drop a point file on the window to open it.";

// State shared with the GLFW callbacks (through the window's user pointer).
struct Session {
  const ViewerOptions* options = nullptr;
  GLFWwindow* window = nullptr;
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<GpuPointCloud> cloud;
  DrawSet draw_set;  // all of `cloud`'s chunks
  RenderSettings settings;
  StereoSettings stereo;
  bool quad_buffer = false;  // the window has left and right back buffers
  Camera camera;
  CameraController controller;
  std::string loaded_name;
  std::string status;  // last message for the user: errors, screenshot paths
  bool show_help = false, show_panel = true, vsync = true;
  bool screenshot_requested = false;
  int screenshot_count = 0;
  double scroll_steps = 0;
  std::vector<std::string> dropped;
  double last_click_time = -1;
  bool pick_requested = false;
  // What the last drawn picture shows: points are drawn again only when one of these changes
  // (on llvmpipe a large cloud takes a good part of a second), otherwise the picture is reused.
  struct Drawn {
    const GpuPointCloud* cloud = nullptr;
    Camera camera;
    RenderSettings settings;
    StereoSettings stereo;
    int width = 0, height = 0;
    friend bool operator==(const Drawn&, const Drawn&) = default;
  };
  std::optional<Drawn> drawn;
};

Session& sessionOf(GLFWwindow* window) {
  return *static_cast<Session*>(glfwGetWindowUserPointer(window));
}

void fitCamera(Session& s) {
  if (!s.cloud) return;
  int width = 1, height = 1;
  glfwGetFramebufferSize(s.window, &width, &height);
  s.camera.fitToBounds(s.cloud->bounds(), double(width) / std::max(height, 1));
}

void openFile(Session& s, const std::filesystem::path& path, bool first) {
  try {
    PointCloud cloud = readPointFile(path);
    auto gpu = std::make_unique<GpuPointCloud>(cloud);
    s.cloud = std::move(gpu);
    s.draw_set = s.cloud->drawSet();
    s.loaded_name = path.filename().string();
    int width = 1, height = 1;
    glfwGetFramebufferSize(s.window, &width, &height);
    const double aspect = double(width) / std::max(height, 1);
    if (first && s.options->initial_camera) {
      s.camera = s.options->initial_camera(s.cloud->bounds(), aspect);
    } else {
      s.camera = defaultCameraFor(s.cloud->bounds(), aspect);
    }
    const auto size = s.cloud->bounds().size();
    s.controller.fly_speed =
        0.2 * std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
    if (s.settings.world_size <= 0) s.settings.world_size = float(2.0 * s.cloud->typicalSpacing());
    s.status =
        "opened " + path.string() + " (" + std::to_string(s.cloud->pointCount()) + " points)";
    glfwSetWindowTitle(s.window, (s.options->title + " - " + s.loaded_name).c_str());
  } catch (const std::exception& e) {
    // Keep whatever was shown before; say why the new file is not.
    s.status = std::string("cannot open ") + path.string() + ": " + e.what();
  }
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

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

void onKey(GLFWwindow* window, int key, int, int action, int) {
  if ((action != GLFW_PRESS && action != GLFW_REPEAT) || ImGui::GetIO().WantCaptureKeyboard) return;
  Session& s = sessionOf(window);
  // Held keys repeat only for the stereo adjustments.
  const bool adjust = key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET ||
                      key == GLFW_KEY_MINUS || key == GLFW_KEY_EQUAL;
  if (action == GLFW_REPEAT && !adjust) return;
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
    case GLFW_KEY_X:
      s.stereo.swap_eyes = !s.stereo.swap_eyes;
      s.status = s.stereo.swap_eyes ? "stereo eyes swapped" : "stereo eyes not swapped";
      break;
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window, GLFW_TRUE);
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
      break;
    case GLFW_KEY_P:
      s.screenshot_requested = true;
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

void onMouseButton(GLFWwindow* window, int button, int action, int) {
  if (ImGui::GetIO().WantCaptureMouse || button != GLFW_MOUSE_BUTTON_LEFT || action != GLFW_PRESS) {
    return;
  }
  Session& s = sessionOf(window);
  const double now = glfwGetTime();
  if (now - s.last_click_time < 0.35) s.pick_requested = true;
  s.last_click_time = now;
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
  Session& s = sessionOf(window);
  if (count > 0) s.dropped.emplace_back(paths[0]);  // one cloud at a time: the first file
}

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

void drawPanel(Session& s, double frame_seconds, const FrameStats& stats) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Parallax");
  ImGui::Text("%s", s.loaded_name.empty() ? "(no cloud: drop a file here)" : s.loaded_name.c_str());
  // The last frame that drew points (frames that reuse the picture cost next to nothing).
  ImGui::Text("frame %.1f ms, %.1f FPS", frame_seconds * 1e3,
              frame_seconds > 0 ? 1.0 / frame_seconds : 0.0);
  ImGui::Text("points drawn %llu of %llu", static_cast<unsigned long long>(stats.points_drawn),
              static_cast<unsigned long long>(s.cloud ? s.cloud->pointCount() : 0));
  ImGui::Text("GPU memory %.1f MB", s.cloud ? double(s.cloud->gpuBytes()) / 1e6 : 0.0);
  if (ImGui::Checkbox("vsync (V)", &s.vsync)) glfwSwapInterval(s.vsync ? 1 : 0);

  RenderSettings& r = s.settings;
  ImGui::Separator();
  ImGui::TextDisabled("Points");
  comboOf("colour", r.color,
          std::array{ColorMode::Rgb, ColorMode::Elevation, ColorMode::Intensity, ColorMode::Normal,
                     ColorMode::Classification, ColorMode::Uniform},
          colorModeName);
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
  ImGui::TextDisabled("H: keys and mouse");
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

void writeScreenshot(Session& s, int width, int height) {
  std::vector<std::uint8_t> bottom_up(std::size_t(width) * height * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  RgbaImage image{width, height, std::vector<std::uint8_t>(bottom_up.size())};
  const std::size_t row = std::size_t(width) * 4;
  for (int y = 0; y < height; ++y) {
    std::memcpy(image.pixels.data() + y * row, bottom_up.data() + (height - 1 - y) * row, row);
    for (std::size_t x = 3; x < row; x += 4) image.pixels[y * row + x] = 255;  // opaque
  }
  const auto path = s.options->screenshot_dir /
                    ("parallax-screenshot-" + std::to_string(++s.screenshot_count) + ".png");
  try {
    // Written under another name and renamed, so that a watcher never reads half a file.
    const auto partial = std::filesystem::path(path.string() + ".partial");
    writePng(partial, image);
    std::filesystem::rename(partial, path);
    s.status = "screenshot: " + std::filesystem::absolute(path).string();
  } catch (const std::exception& e) {
    s.status = std::string("screenshot failed: ") + e.what();
  }
  std::printf("%s\n", s.status.c_str());
  std::fflush(stdout);
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

void onGlfwError(int code, const char* description) {
  std::fprintf(stderr, "parallax view: GLFW error 0x%x: %s\n", code, description);
}

}  // namespace

int runViewer(const ViewerOptions& options) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) {
    throw std::runtime_error(
        "cannot open a window: GLFW found no display (is DISPLAY set? use `parallax render` "
        "without one)");
  }
  struct GlfwGuard {
    ~GlfwGuard() { glfwTerminate(); }
  } glfw_guard;
  const bool debug = glDebugRequested();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
  const bool want_quad_buffer = options.stereo.mode == StereoMode::QuadBuffer;
  glfwWindowHint(GLFW_STEREO, want_quad_buffer ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!window && want_quad_buffer) {
    // GLFW_STEREO is a hard constraint: without a stereo visual no window at all. Try again
    // without; the session then falls back to sbs.
    glfwWindowHint(GLFW_STEREO, GLFW_FALSE);
    window =
        glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  }
  if (!window) {
    throw GlContextError(
        "cannot create a window with an OpenGL 4.5 core context (see the GLFW error above); "
        "Parallax needs OpenGL 4.5 core: with Mesa, install 'libgl1-mesa-dri'");
  }
  struct WindowGuard {
    GLFWwindow* window;
    ~WindowGuard() { glfwDestroyWindow(window); }
  } window_guard{window};
  glfwMakeContextCurrent(window);
  auto context = GlContext::adoptCurrent({debug});

  Session s;
  s.options = &options;
  s.window = window;
  s.settings = options.settings;
  s.stereo = options.stereo;
  GLboolean stereo_buffers = GL_FALSE;
  glGetBooleanv(GL_STEREO, &stereo_buffers);
  s.quad_buffer = stereo_buffers == GL_TRUE;
  if (s.stereo.mode != StereoMode::Mono) setStereoMode(s, s.stereo.mode);
  s.vsync = options.vsync;
  s.renderer = std::make_unique<Renderer>();
  glfwSwapInterval(s.vsync ? 1 : 0);
  glfwSetWindowUserPointer(window, &s);
  // Ours first: ImGui's backend chains to callbacks installed before it.
  glfwSetKeyCallback(window, onKey);
  glfwSetScrollCallback(window, onScroll);
  glfwSetMouseButtonCallback(window, onMouseButton);
  glfwSetDropCallback(window, onDrop);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 450 core");
  struct ImGuiGuard {
    ~ImGuiGuard() {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
  } imgui_guard;

  std::fprintf(stderr, "parallax view: OpenGL %s on %s\n", context->version().c_str(),
               context->renderer().c_str());
  if (!options.input.empty()) openFile(s, options.input, true);

  auto last = std::chrono::steady_clock::now();
  double frame_seconds = 0;
  FrameStats stats;
  bool busy = true;  // drew points or had input last frame: poll; otherwise wait for events
  while (!glfwWindowShouldClose(window)) {
    if (busy) {
      glfwPollEvents();
    } else {
      glfwWaitEventsTimeout(0.1);
    }
    for (const std::string& path : s.dropped) openFile(s, path, false);
    s.dropped.clear();
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;

    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    if (width <= 0 || height <= 0) continue;  // minimised

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();

    const InputState input = readInput(window);
    busy = input.left || input.right || input.middle ||
           (s.controller.fly && (input.forward || input.back || input.left_key || input.right_key ||
                                 input.up || input.down));
    s.controller.update(s.camera, input, width, height, std::min(dt, 0.1));
    if (s.scroll_steps != 0) {
      s.controller.scroll(s.camera, s.scroll_steps, input.cursor_x, input.cursor_y, width, height);
      s.scroll_steps = 0;
    }
    if (s.pick_requested) {
      s.pick_requested = false;
      // Window coordinates are top-down, GL's bottom-up.
      if (auto picked = s.renderer->pick(int(input.cursor_x), height - 1 - int(input.cursor_y))) {
        s.camera.pivot = *picked;
        s.status = "pivot set";
      }
    }

    if (s.cloud) {
      const StereoFrame frame = stereoFrame(s.camera, s.stereo, width, height);
      const Session::Drawn now_showing{s.cloud.get(), s.camera, s.settings,
                                       s.stereo,      width,    height};
      if (s.drawn != now_showing ||
          !s.renderer->composite(frame.views, s.settings, 0, width, height, frame.composition)) {
        const auto start = std::chrono::steady_clock::now();
        stats = s.renderer->render(s.draw_set, frame, s.settings, 0, width, height);
        frame_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        s.drawn = now_showing;
        busy = true;
      }
    } else {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      glClearColor(s.settings.background[0], s.settings.background[1], s.settings.background[2], 1);
      glClear(GL_COLOR_BUFFER_BIT);
    }

    if (s.show_panel) drawPanel(s, frame_seconds, stats);
    if (s.show_help) drawHelp();
    ImGui::Render();
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (s.screenshot_requested) {
      s.screenshot_requested = false;
      writeScreenshot(s, width, height);
    }
    glfwSwapBuffers(window);
  }
  return 0;
}

}  // namespace parallax
