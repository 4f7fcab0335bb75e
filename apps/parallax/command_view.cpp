// `parallax view [INPUT]`: the interactive viewer (src/viewer) with the same render and level of
// detail options as `parallax render`. INPUT may be a Potree 2.0 directory or its URL; a file with
// more points than --budget shows a sample at once and its octree once built (viewer/viewer.h).
#include <chrono>
#include <memory>
#include <string>

#include "commands.h"
#include "network_options.h"
#include "render_options.h"
#include "viewer/viewer.h"

namespace parallax::cli {
namespace {

struct ViewCommandOptions {
  std::string input;
  int width = 1280, height = 720;
  bool no_vsync = false;
  std::string screenshot_dir = ".";
  RenderOptions render;
  LodOptions lod;
};

int runView(const ViewCommandOptions& o, std::chrono::steady_clock::time_point start) {
  configureNetworkFrom(o.lod);
  ViewerOptions viewer;
  viewer.start_time = start;
  viewer.lod = lodFrameSettingsFrom(o.lod);
  viewer.cache = octreeCacheSettingsFrom(o.lod);
  viewer.input = o.input;
  viewer.width = o.width;
  viewer.height = o.height;
  viewer.vsync = !o.no_vsync;
  viewer.screenshot_dir = o.screenshot_dir;
  // World size and spacing are only known once the cloud is loaded: 0 asks the viewer to choose.
  viewer.settings = renderSettingsFrom(o.render, 0.0);
  if (o.render.world_size <= 0) viewer.settings.world_size = 0.0f;
  viewer.stereo = stereoSettingsFrom(o.render);
  const RenderOptions render = o.render;
  viewer.initial_camera = [render](const Bounds3& bounds, double aspect) {
    return cameraFrom(render, bounds, aspect);
  };
  return runViewer(viewer);
}

}  // namespace

Command addViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewCommandOptions>();
  Command command;
  CLI::App* sub = app.add_subcommand("view", "Open a point file in a window (H in it: keys)");
  sub->add_option("input", options->input,
                  "Point file (PLY, LAS or text) or Potree 2.0 directory (or its http(s) URL); or "
                  "drop one on the window");
  sub->add_option("--width", options->width, "Window width")->capture_default_str();
  sub->add_option("--height", options->height, "Window height")->capture_default_str();
  sub->add_flag("--no-vsync", options->no_vsync, "Start with vsync off (V toggles it)");
  sub->add_option("--screenshot-dir", options->screenshot_dir,
                  "Folder for screenshots (P) and saved cameras")
      ->capture_default_str();
  addRenderOptions(*sub, options->render);
  addLodOptions(*sub, options->lod);
  command.subcommand = sub;
  // The first picture's time counts from here, after the option parsing (microseconds).
  command.run = [options] { return runView(*options, std::chrono::steady_clock::now()); };
  return command;
}

}  // namespace parallax::cli
