#include "viewer/viewer.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_internal.h>  // ClosePopupToLevel: Esc closes an open list

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/point_cloud.h"
#include "io/ply_preview.h"
#include "io/point_file.h"
#include "lod/drawing_input.h"
#include "lod/octree_open.h"
#include "lod/octree_url.h"
#include "lod/potree_reader.h"
#include "render/draw_set_layers.h"
#include "render/frame_step.h"
#include "render/gl_context.h"
#include "render/image_file.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/progressive.h"
#include "render/renderer.h"
#include "viewer/viewer_session.h"

namespace parallax {
namespace viewer_internal {

Session& sessionOf(GLFWwindow* window) {
  return *static_cast<Session*>(glfwGetWindowUserPointer(window));
}

// The first eye's view of the window (the whole window in mono) and the fraction of its width
// right of the panel; 1 where the panel is hidden, or where it leaves too little to fit into.
struct FreeView {
  double aspect = 1;  // the view's projection aspect
  double free_fraction = 1;
};

FreeView freeView(const Session& s) {
  int width = 1, height = 1;
  glfwGetFramebufferSize(s.window, &width, &height);
  const StereoFrame frame =
      stereoFrame(s.camera, s.stereo, std::max(width, 1), std::max(height, 1));
  const View& view = frame.views.front();
  FreeView free{view.aspect(), 1.0};
  const double panel_right = !s.show_panel             ? 0.0
                             : s.panel_right           ? double(*s.panel_right)
                             : panelStartsCollapsed(s) ? 0.0
                                                       : 10.0 + panelWidth();
  // Viewport x is in output pixels for the modes drawn into the output's halves; the composed
  // modes draw each eye full size from x 0, as the window shows it.
  const double covered =
      std::clamp(panel_right - view.viewport.x, 0.0, double(view.viewport.width));
  const double fraction = 1.0 - covered / std::max(view.viewport.width, 1);
  // Under about a third left free, a cloud framed there would be a thumbnail: the whole view.
  if (fraction >= 0.35) free.free_fraction = fraction;
  return free;
}

void fitCamera(Session& s) {
  const FreeView free = freeView(s);
  parallax::fitCamera(s.camera, s.extent, free.aspect, 1.0 - 2.0 * free.free_fraction, 1.0);
}

// The first camera for a newly opened cloud (s.extent): the command line's for the first file.
void placeCamera(Session& s, bool first) {
  const FreeView free = freeView(s);
  const double x_from = 1.0 - 2.0 * free.free_fraction;
  if (first && s.options->initial_camera) {
    s.camera = s.options->initial_camera(s.extent, free.aspect);
    // A fitted camera, not one the user gave: fitted again into the part right of the panel.
    if (s.options->initial_camera_fits && x_from > -1.0) {
      parallax::fitCamera(s.camera, s.extent, free.aspect, x_from, 1.0);
    }
  } else {
    s.camera = defaultCameraFor(s.extent, free.aspect, x_from, 1.0);
  }
  const auto size = s.extent.bounds.size();
  s.controller.fly_speed =
      0.2 * std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
}

// The look of a newly opened cloud, where the options leave it to the viewer.
void chooseLook(Session& s, bool spacing_known, bool has_normals) {
  s.settings = viewerLook(s.settings, s.options->settings,
                          {.size = s.options->choose_size, .lighting = s.options->choose_lighting},
                          {.spacing_known = spacing_known, .has_normals = has_normals});
}

void setTitle(Session& s, const std::filesystem::path& path) {
  s.loaded_name = path.filename().string();
  if (s.loaded_name.empty()) s.loaded_name = path.parent_path().filename().string();
  glfwSetWindowTitle(s.window, (s.options->title + " - " + s.loaded_name).c_str());
}

void uploadShownCloud(Session& s) {
  const PointCloud& cloud = *s.cloud_points;
  s.scalar_error.clear();
  std::unique_ptr<GpuPointCloud> gpu;
  if (!s.settings.scalar.field.empty()) {
    try {
      PointCloud painted = cloud.clone();
      s.shown_scalar_range = paintScalarField(painted, s.settings.scalar);
      gpu = std::make_unique<GpuPointCloud>(painted);
    } catch (const std::invalid_argument& e) {
      s.scalar_error = e.what();
    }
  }
  if (!gpu) gpu = std::make_unique<GpuPointCloud>(cloud);
  s.shown_scalar = s.settings.scalar;
  s.pick_source.reset();
  s.cloud = std::move(gpu);
  s.draw_set = s.cloud->drawSet();
  s.drawn.reset();
}

// Uploads a whole cloud (a file, or a large file's preview: `whole` false) as what is shown.
void showCloud(Session& s, PointCloud cloud_points, bool whole, bool place_camera, bool first) {
  s.cloud_points = std::make_unique<PointCloud>(std::move(cloud_points));
  s.cloud_file.clear();  // (openCloudFile sets it again where the file holds more)
  s.cloud_file_attributes.clear();
  const PointCloud& cloud = *s.cloud_points;
  s.picked.reset();
  s.previous_lod.reset();
  s.lod.reset();
  s.octree.reset();
  s.lod_location.reset();
  uploadShownCloud(s);
  s.extent = viewExtentOf(cloud);
  if (place_camera) placeCamera(s, first);
  chooseLook(s, s.cloud->typicalSpacing() > 0, s.cloud->hasNormals());
  if (s.settings.world_size <= 0) s.settings.world_size = float(2.0 * s.cloud->typicalSpacing());
  prepareFilters(s, &cloud, whole, cloud.hasClassification(), first);
}

// The panel changed the scalar colouring of a whole cloud: upload it again with the new colours.
void refreshScalarColors(Session& s) {
  if (s.cloud && s.cloud_points && s.settings.scalar != s.shown_scalar) uploadShownCloud(s);
}

// Opens an octree (a Potree directory or a COPC file) as what is shown. With `keep_camera` (the
// switch from a preview to its octree) the camera stays, and the preview is drawn until the octree
// draws something.
void showOpenedOctree(Session& s, std::unique_ptr<Octree> octree,
                      std::unique_ptr<OctreeLocation> location, bool keep_camera, bool first) {
  s.previous_lod.reset();
  s.lod.reset();
  s.octree = std::move(octree);
  s.lod_location = std::move(location);
  s.drawn.reset();
  s.picked.reset();
  s.pick_source.reset();
  s.extent = viewExtentOf(*s.octree);
  if (!keep_camera) {  // (a preview's camera and look stay for its octree)
    s.cloud.reset();
    s.cloud_points.reset();
    placeCamera(s, first);
    chooseLook(s, s.octree->info().spacing > 0, s.octree->info().has_normals);
    prepareFilters(s, nullptr, false, s.octree->info().has_classification, first);
  }
  // The attenuated size needs a spacing before any node is drawn: about a level-3 node's.
  if (s.settings.world_size <= 0) s.settings.world_size = float(s.octree->info().spacing / 4.0);
  startLodScene(s);  // once the look is chosen: the nodes are read with what it draws
  if (!s.settings.scalar.field.empty()) {
    s.status = "colour by " + s.settings.scalar.field +
               ": scalar attributes are coloured on whole clouds; the octree is drawn without";
  }
}

void showOctree(Session& s, const std::filesystem::path& directory,
                std::unique_ptr<OctreeLocation> location, bool keep_camera, bool first) {
  showOpenedOctree(s, openOctree(directory), std::move(location), keep_camera, first);
}

// A URL is opened on a thread of its own (a few requests): the window answers meanwhile, and
// keeps showing what it showed until the octree is there.
void startOpeningUrl(Session& s, const std::string& url, bool first) {
  checkOctreeUrl(url);
  s.opening.reset();  // an earlier open still under way ends first (bounded by its timeouts)
  // Assigned, not emplace()d: clang 14 does not see the nested struct with member initializers
  // as default-constructible inside its enclosing class.
  s.opening = Session::OpeningUrl{
      .url = url, .first = first, .octree = std::async(std::launch::async, [url] {
                                    return openOctreeUrl(url);
                                  })};
  s.status = "opening " + url;
}

void pollOpeningUrl(Session& s) {
  if (!s.opening ||
      s.opening->octree.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  Session::OpeningUrl opening = std::move(*s.opening);
  s.opening.reset();
  try {
    showOpenedOctree(s, opening.octree.get(), nullptr, false, opening.first);
    s.status = "opened the octree " + opening.url + " (" +
               std::to_string(s.octree->info().point_count) + " points)";
    setTitle(s, opening.url);
    s.error.clear();
  } catch (const std::exception& e) {
    s.status = "cannot open " + opening.url + ": " + e.what();
    s.error = s.status;
  }
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

// A file over the budget: its cached octree, or a preview while the octree is built.
void openLargeFile(Session& s, const std::filesystem::path& path, std::uint64_t points,
                   bool first) {
  auto location = std::make_unique<OctreeLocation>(path, s.options->cache);
  const std::filesystem::path directory = location->directory();
  if (location->complete()) {
    showOctree(s, directory, std::move(location), false, first);
    s.status = "opened " + path.string() + " (" + std::to_string(points) +
               " points) from its octree in " + directory.string();
    return;
  }
  const std::uint64_t budget = s.lod_settings.selection.point_budget;
  std::uint64_t shown = 0;
  if (std::optional<PointCloud> preview = readDrawingPreview(path, budget)) {
    shown = preview->count;
    showCloud(s, std::move(*preview), false, true, first);
  } else {
    // No sample reader for text: nothing is shown until the octree is ready.
    s.cloud.reset();
    s.cloud_points.reset();
    s.previous_lod.reset();
    s.lod.reset();
    s.octree.reset();
    s.lod_location.reset();
  }
  s.build_pending = std::move(location);
  s.build_keeps_camera = shown > 0;
  s.build_first = first;
  s.status = path.string() + " has " + std::to_string(points) + " points, over the budget of " +
             std::to_string(budget) + ": showing a sample of " + std::to_string(shown) +
             " while its octree is built in " + directory.string();
}

// Starts the pending build: after the first picture of its preview has been shown.
void startBuild(Session& s) {
  if (!s.build_pending) return;
  s.build.reset();  // an earlier build ends first (it cannot be interrupted)
  OctreeBuildOptions build = s.options->cache.build;
  // One core stays with the frame loop, so that the window answers while the octree is built.
  if (build.threads == 0)
    build.threads = int(std::max(2u, std::thread::hardware_concurrency())) - 1;
  s.build = std::make_unique<BackgroundOctreeBuild>(std::move(s.build_pending), build);
}

// Switches to the octree once the background build has finished, or reports its failure.
void pollBuild(Session& s) {
  if (!s.build) return;
  const BackgroundOctreeBuild::Status status = s.build->status();
  if (!status.finished) return;
  const double seconds = s.build->secondsElapsed();
  auto location = s.build->takeLocation();
  s.build.reset();
  if (!status.error.empty()) {
    s.status = "building the octree failed: " + status.error;
    s.error = s.status;
  } else {
    try {
      const std::filesystem::path directory = location->directory();
      showOctree(s, directory, std::move(location), s.build_keeps_camera, s.build_first);
      char text[64];
      std::snprintf(text, sizeof text, " (built in %.1f s)", seconds);
      s.status = "switched to the level-of-detail octree in " + directory.string() + text;
    } catch (const std::exception& e) {
      s.status = std::string("cannot open the octree just built: ") + e.what();
      s.error = s.status;
    }
  }
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

void openFile(Session& s, const std::filesystem::path& path, bool first) {
  try {
    if (octreeUrlKind(path.string()) != OctreeUrlKind::NotUrl) {
      startOpeningUrl(s, path.string(), first);
    } else if (const DrawingInput drawing =
                   planDrawing(path, s.lod_settings.selection.point_budget);
               drawing.kind == DrawingKind::Octree) {
      showOctree(s, path, nullptr, false, first);
      s.status = "opened the octree " + path.string() + " (" +
                 std::to_string(s.octree->info().point_count) + " points)";
      setTitle(s, path);
    } else if (drawing.kind == DrawingKind::OverBudget) {
      openLargeFile(s, path, drawing.points, first);
      setTitle(s, path);
    } else {
      openCloudFile(s, path, first);
      s.status =
          "opened " + path.string() + " (" + std::to_string(s.cloud->pointCount()) + " points)";
      setTitle(s, path);
    }
    s.shown_path = path;
    s.error.clear();
  } catch (const std::exception& e) {
    // Keep whatever was shown before; say why the new file is not.
    s.status = std::string("cannot open ") + path.string() + ": " + e.what();
    s.error = s.status;
  }
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

// Ctrl + click and the measurement tools: answered in the frame of the click, after the frame is
// drawn. The draw set is the one drawn: the cloud (or preview) while there is one, else the
// octree's last selection.
std::optional<PickResult> pickAt(Session& s, int x, int y, int width, int height) {
  if (!s.cloud && !s.lod) return std::nullopt;
  completeCloud(s);  // a picked point reports every attribute of the file
  const void* scene = s.cloud ? static_cast<const void*>(s.cloud.get()) : s.lod.get();
  if (s.pick_scene != scene || !s.pick_source) {
    s.pick_source = s.cloud ? std::make_unique<PickSource>(*s.cloud_points)
                            : std::make_unique<PickSource>(*s.octree);
    s.pick_scene = scene;
  }
  const DrawSet& draw_set = s.cloud ? s.draw_set : s.lod->drawSet();
  const StereoFrame frame = stereoFrame(s.camera, s.stereo, width, height);
  PickRequest request;
  request.x = x, request.y = y;
  // The pick's offscreen frame (compute, no multisampling or eye-dome lighting) is now the
  // renderer's last picture: the next frame draws the window's own again rather than reuse it.
  s.drawn.reset();
  std::optional<PickResult> picked;
  try {
    // The window's picture may be GL_POINTS' or a progressive part: picking draws the whole
    // frame again with the compute rasterizer (render/point_picker.h).
    picked = pickPoint(*s.renderer, *s.pick_source, draw_set, frame.views, frame.composition,
                       s.settings, width, height, request);
  } catch (const std::exception& e) {  // an octree node that cannot be read again
    s.status = std::string("cannot pick: ") + e.what();
    std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
    return std::nullopt;
  }
  if (!picked) {
    s.status = "no point under the cursor";
    std::fprintf(stderr, "parallax view: picked nothing at %d,%d\n", x, height - 1 - y);
  }
  return picked;
}

// Ctrl + click: the point under the cursor (bottom-left origin) and its attributes, in the
// panel's "Picked point" and on stderr.
void pickPointAt(Session& s, int x, int y, int width, int height) {
  s.picked = pickAt(s, x, y, width, height);
  if (!s.picked) return;
  std::string line = "parallax view: picked";
  for (const PointAttribute& attribute : s.picked->attributes) {
    const bool position = attribute.name == "x" || attribute.name == "y" || attribute.name == "z";
    line += " ";
    if (!position) line += attribute.name + "=";
    line += formatAttributeValue(attribute.value);
  }
  std::fprintf(stderr, "%s\n", line.c_str());
  s.status = "picked a point (panel: Picked point)";
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
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

// A switch set in the environment: set, and neither empty nor "0".
bool environmentFlag(const char* name) {
  const char* value = std::getenv(name);
  return value && *value != '\0' && std::strcmp(value, "0") != 0;
}

void onGlfwError(int code, const char* description) {
  std::fprintf(stderr, "parallax view: GLFW error 0x%x: %s\n", code, description);
}

}  // namespace viewer_internal

int runViewer(const ViewerOptions& options) {
  using namespace viewer_internal;
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
  // Without a stereo visual the first try fails with GLFW's "format unavailable" (0x10009): that
  // is the expected case of the fallback below, which tells the user in words, so it is not
  // printed raw.
  if (want_quad_buffer) glfwSetErrorCallback(nullptr);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  glfwSetErrorCallback(onGlfwError);
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
  s.lod_settings = options.lod;
  s.frame_budget_ms = options.frame_budget_ms;
  GLboolean stereo_buffers = GL_FALSE;
  glGetBooleanv(GL_STEREO, &stereo_buffers);
  s.quad_buffer = stereo_buffers == GL_TRUE;
  if (s.stereo.mode != StereoMode::Mono) setStereoMode(s, s.stereo.mode);
  s.vsync = options.vsync;
  s.renderer = std::make_unique<Renderer>();
  s.measure.document = options.measurements;
  s.measure.file = options.measurements_file.empty()
                       ? (options.screenshot_dir / "measurements.json").string()
                       : options.measurements_file.string();
  s.measure.profile_width = options.profile_width;
  {
    VolumeOptions base;  // the base parsed as `parallax volume --base` parses it
    setVolumeBase(base, options.volume_base);
    s.measure.volume_base = base.base;
    s.measure.volume_base_file = base.base_raster.string();
  }
  setMeasureTool(s, options.measure_tool);
  s.process.steps = options.process_steps;
  s.process.output = options.process_output.string();
  s.status.clear();
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
  s.raster_ramp = options.raster_ramp;
  prepareRegistration(s, options.register_with, options.write_transform, options.pick_pairs);
  if (!options.raster.empty()) {
    const std::string path = options.raster.string();
    path.copy(s.raster_path_text.data(), s.raster_path_text.size() - 1);
    loadRasterLayer(s, options.raster);
  }

  s.trace_keys = environmentFlag("PARALLAX_VIEW_TRACE_KEYS");
  s.process.hold_first_report = environmentFlag("PARALLAX_VIEW_TEST_HOLD_PROCESS");
  auto last = std::chrono::steady_clock::now();
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
    // A moving camera's frame lasts from this frame's start to the next's, all included.
    if (s.moved_last_frame) s.moving_frames.add(dt);
    s.moved_last_frame = false;

    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    if (width <= 0 || height <= 0) continue;  // minimised

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (s.close_popups) {
      s.close_popups = false;
      ImGui::ClosePopupToLevel(0, true);
    }

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

    pollBuild(s);
    pollOpeningUrl(s);
    if (updateMeasureFlight(s)) busy = true;
    updateOverlay(s);
    updateCloudAttributes(s);
    refreshScalarColors(s);
    updateLodAttributes(s);
    updateProcessing(s);
    updateRegistration(s);
    if (s.cloud || s.lod) {
      const StereoFrame frame = stereoFrame(s.camera, s.stereo, width, height);
      const void* scene = s.lod ? static_cast<const void*>(s.lod.get()) : s.cloud.get();
      const Session::Drawn now_showing{scene,
                                       s.lod_settings.selection.point_budget,
                                       s.lod_settings.selection.min_node_size_px,
                                       s.camera,
                                       s.settings,
                                       s.stereo,
                                       width,
                                       height};
      // A scene still streaming is drawn every frame until it has everything it selected, and
      // a picture refined progressively until it is complete.
      const bool streaming = s.lod && !s.lod->complete();
      bool changed = s.drawn != now_showing;
      if (changed && s.drawn && s.drawn->camera != now_showing.camera) s.moved_last_frame = true;
      const bool refining = s.frame_budget_ms > 0 && !s.progressive.complete();
      bool draw = streaming || changed || refining;
      if (!draw &&
          !s.renderer->composite(frame.views, s.settings, 0, width, height, frame.composition)) {
        draw = changed = true;  // (another size or composition: the picture starts again)
      }
      if (draw) {
        const auto start = std::chrono::steady_clock::now();
        const DrawSet* draw_set = &s.draw_set;
        const RenderSettings* look = &s.settings;
        DrawSet prioritized;
        // A whole cloud (or a preview) is refined too: its chunks, largest-looking first.
        bool refine = s.frame_budget_ms > 0;
        if (s.lod) {
          const DrawSet& streamed = s.lod->update(frame.views, s.lod_settings);
          s.lod_stats = s.lod->stats();
          if (const DrawSet* previous = previousLodPicture(s, look, changed)) {
            draw_set = previous;  // (whole, in its own look: no refinement on top of it)
            refine = false;
          } else if (!streamed.items.empty() || !s.cloud) {
            // A preview stays until the octree draws something in its place.
            draw_set = &streamed;
            s.cloud.reset();
            s.cloud_points.reset();
          }
        }
        if (refine && draw_set == &s.draw_set) {
          prioritized = prioritizedDrawSet(s.draw_set, frame.views);
          draw_set = &prioritized;
        }
        if (refine) {
          ProgressiveSettings progressive = s.progressive.settings();
          progressive.frame_budget_s = s.frame_budget_ms / 1e3;
          s.progressive.setSettings(progressive);
        }
        if (const DrawSet* preview = registrationDrawSet(s)) draw_set = preview;
        DrawSet layered;  // the raster layer after the cloud (raster_panel.cpp)
        if (s.raster_layer) {
          layered = withLayer(*draw_set, s.raster_layer->drawSet());
          draw_set = &layered;
        }
        const FrameStepResult step =
            drawFrameStep(*s.renderer, refine ? &s.progressive : nullptr, *draw_set, frame, *look,
                          0, width, height, changed);
        if (step.drew) {
          stats = step.stats;
          if (!step.part.accumulate) {
            s.picture_start = start, s.picture_points = 0, s.picture_parts = 0;
          }
          ++s.picture_parts;
          s.picture_points += stats.points_drawn;
        }
        if (refine) {
          if (s.progressive.complete() && s.picture_parts > 1 && !s.refined_picture_reported) {
            s.refined_picture_reported = true;
            std::fprintf(
                stderr,
                "parallax view: first picture refined to completion in %d parts (%llu points, "
                "%.3f s)\n",
                s.picture_parts, static_cast<unsigned long long>(s.picture_points),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - s.picture_start)
                    .count());
          }
        }
        s.picture_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - s.picture_start)
                .count();
        s.drawn = now_showing;
        busy = true;
        if (!s.first_picture_reported && stats.points_drawn > 0) {
          s.first_picture_reported = true;
          std::fprintf(stderr, "parallax view: first picture after %.3f s (%llu points)\n",
                       std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                     s.options->start_time)
                           .count(),
                       static_cast<unsigned long long>(stats.points_drawn));
        }
      }
    } else {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      glClearColor(s.settings.background[0], s.settings.background[1], s.settings.background[2], 1);
      glClear(GL_COLOR_BUFFER_BIT);
    }

    if (s.point_pick_requested) {
      s.point_pick_requested = false;
      pickPointAt(s, int(input.cursor_x), height - 1 - int(input.cursor_y), width, height);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);  // picking may have drawn offscreen; the panel may not
    }
    if (s.measure.click_requested) {
      s.measure.click_requested = false;
      const int x = int(s.measure.click_x), y = height - 1 - int(s.measure.click_y);
      if (pairPickingTakesClicks(s)) {
        pairPickingClick(s, x, y, width, height);
      } else if (const auto picked = pickAt(s, x, y, width, height)) {
        measureClick(s, *picked);
      }
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      busy = true;  // the overlay changed: the next frame shows it
    }
    // P: the picture alone, read before the panel is drawn over it; Shift + P: the window.
    if (s.screenshot_requested && !s.screenshot_with_panel) {
      s.screenshot_requested = false;
      writeScreenshot(s, width, height);
    }
    drawScalarLegendOverlay(s);
    if (s.show_panel) {
      drawPanel(s, stats);
    } else {
      s.panel_right = 0.0f;
    }
    if (!s.cloud && !s.lod) {
      drawEmptyWindowMessage(s);
    } else {
      drawErrorBanner(s);
    }
    if (s.show_help) drawHelp();
    ImGui::Render();
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (s.screenshot_requested) {
      s.screenshot_requested = false;
      writeScreenshot(s, width, height);
    }
    glfwSwapBuffers(window);
    for (const int key : s.keys_this_frame) {
      std::fprintf(stderr, "parallax view: key %d handled and drawn\n", key);
    }
    s.keys_this_frame.clear();
    startBuild(s);
  }
  // What a moving camera felt like, in the figures of `parallax bench render --orbit`.
  if (const FrameTimeSummary moving = s.moving_frames.summary(); moving.frames > 0) {
    std::fprintf(stderr,
                 "parallax view: frames while moving: median %.1f ms, p90 %.1f ms, worst %.1f ms "
                 "(last %zu frames)\n",
                 moving.median_s * 1e3, moving.p90_s * 1e3, moving.worst_s * 1e3, moving.frames);
  }
  if (s.build && !s.build->status().finished) {
    // The conversion cannot be interrupted and may take minutes: end the process here (what a
    // kill would do, less the converter's temporary directory: never a finished-looking one).
    std::fprintf(stderr, "parallax view: quitting during the octree build of %s\n",
                 s.build->location().input().string().c_str());
    s.build->location().abandon();
    std::fflush(nullptr);
    std::_Exit(0);
  }
  return 0;
}

}  // namespace parallax
