// `parallax view [INPUT]`: the interactive viewer (src/viewer) with the same render and level of
// detail options as `parallax render`. INPUT may be a Potree 2.0 directory or a COPC file (or its
// http(s) URL); a file with more points than --budget shows a sample at once and its octree once
// built (viewer/viewer.h). Defaults that differ from `render`'s: without --size-mode,
// --point-size or --shape, points are round and sized to the local spacing (adaptive); without
// --lighting, clouds with normals are lit.
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "io/point_format.h"
#include "measure/measurement_document.h"
#include "network_options.h"
#include "process/process_steps.h"
#include "raster/volume.h"
#include "render_options.h"
#include "viewer/viewer.h"
#include "xr_view.h"

namespace parallax::cli {
namespace {

struct ViewCommandOptions {
  std::string input;
  int width = 1280, height = 720;
  bool no_vsync = false;
  std::string screenshot_dir = ".";
  double frame_budget_ms = 1000.0 / 15.0;
  std::string measurements_file;
  std::string volume_base = "plane";
  std::string tool = "none";
  std::vector<std::string> process_steps;
  std::string process_output;
  std::string raster;
  std::string register_with, write_transform;
  bool pick_pairs = false;
  std::string raster_ramp = "viridis";
  double profile_width = 1.0;
  RenderOptions render;
  LodOptions lod;
  bool xr = false;
  XrViewOptions xr_options;  // its input, render and lod are copied from the above
};

int runView(const ViewCommandOptions& o, const CLI::App& command,
            std::chrono::steady_clock::time_point start) {
  configureNetworkFrom(o.lod);
  if (o.xr) {
    XrViewOptions xr = o.xr_options;
    xr.input = o.input;
    xr.render = o.render;
    xr.lod = o.lod;
    xr.look = viewerLookChoiceFrom(command);
    xr.mirror_width = o.width;
    xr.mirror_height = o.height;
    xr.measurements_file = o.measurements_file;
    xr.profile_width = o.profile_width;
    if (xr.input.empty()) throw std::invalid_argument("--xr needs an INPUT");
    return runXrView(xr);
  }
  ViewerOptions viewer;
  viewer.start_time = start;
  viewer.lod = lodFrameSettingsFrom(o.lod);
  viewer.cache = octreeCacheSettingsFrom(o.lod);
  viewer.input = o.input;
  viewer.width = o.width;
  viewer.height = o.height;
  viewer.vsync = !o.no_vsync;
  viewer.screenshot_dir = o.screenshot_dir;
  viewer.frame_budget_ms = o.frame_budget_ms;
  // World size and spacing are only known once the cloud is loaded: 0 asks the viewer to choose.
  viewer.settings = renderSettingsFrom(o.render, 0.0);
  if (o.render.world_size <= 0) viewer.settings.world_size = 0.0f;
  viewer.stereo = stereoSettingsFrom(o.render);
  const auto tool = measureToolFromName(o.tool);
  if (!tool) {
    throw std::invalid_argument("--tool " + o.tool +
                                ": expected none, point, distance, height, area, angle, profile "
                                "or annotation");
  }
  viewer.measure_tool = *tool;
  viewer.profile_width = o.profile_width;
  viewer.volume_base = o.volume_base;
  VolumeOptions volume_base;
  setVolumeBase(volume_base, o.volume_base);
  if (volume_base.base == VolumeBase::Raster) {
    // A typo is an error here, before the window opens.
    requireBaseRasterFile("--volume-base", volume_base.base_raster);
  }
  for (const std::string& step : o.process_steps) {
    (void)parseProcessStep(step);  // a typo is an error here, before the window opens
    viewer.process_steps.push_back(step);
  }
  viewer.process_output = o.process_output;
  viewer.length_unit = o.render.length_unit;
  viewer.raster = o.raster;
  viewer.register_with = o.register_with;
  viewer.write_transform = o.write_transform;
  viewer.pick_pairs = o.pick_pairs;
  if (o.pick_pairs && o.register_with.empty()) {
    throw std::invalid_argument("--pick-pairs: give the target with --register-with TARGET");
  }
  if (!o.register_with.empty() && o.write_transform.empty()) {
    viewer.write_transform = std::filesystem::path(o.screenshot_dir) /
                             (std::filesystem::path(o.input).stem().string() + "-to-" +
                              std::filesystem::path(o.register_with).stem().string() + ".txt");
  }
  const auto raster_ramp = parseColorRamp(o.raster_ramp);
  if (!raster_ramp) {
    throw std::invalid_argument("--raster-ramp: unknown ramp '" + o.raster_ramp + "' (use " +
                                colorRampNames() + ")");
  }
  viewer.raster_ramp = *raster_ramp;
  if (!o.measurements_file.empty()) {
    // Read before the window opens: a malformed file is reported like a bad point file.
    viewer.measurements = loadMeasurementDocument(o.measurements_file);
    viewer.measurements_file = o.measurements_file;
  }
  const RenderOptions render = o.render;
  // The measurement file's camera for the first cloud, unless camera options are given.
  std::optional<Camera> saved = viewer.measurements.camera;
  if (!render.eye.empty() || !render.camera_file.empty()) saved.reset();
  viewer.initial_camera_fits = !saved && render.eye.empty() && render.camera_file.empty();
  viewer.initial_camera = [render, saved](const ViewExtent& extent, double aspect) {
    return saved ? *saved : cameraFrom(render, extent, aspect);
  };
  // Unlike `render` (whose fixed 1-pixel, unlit default scripts rely on), the viewer shows
  // surfaces by default: adaptive size and lighting where the cloud allows, unless asked otherwise.
  const ViewerLookChoice choice = viewerLookChoiceFrom(command);
  viewer.choose_size = choice.size;
  viewer.choose_lighting = choice.lighting;
  return runViewer(viewer);
}

}  // namespace

Command addViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewCommandOptions>();
  Command command;
  CLI::App* sub = app.add_subcommand("view", "Open a point file in a window (H in it: keys)");
  sub->add_option(
      "input", options->input,
      "Point file (" + pointFormatNamesText() +
          "), Potree 2.0 directory or COPC file (or its http(s) URL); or drop one on the window");
  sub->add_option("--width", options->width, "Window width")->capture_default_str();
  sub->add_option("--height", options->height, "Window height")->capture_default_str();
  sub->add_flag("--no-vsync", options->no_vsync, "Start with vsync off (V toggles it)");
  sub->add_option("--screenshot-dir", options->screenshot_dir,
                  "Folder for screenshots (P) and saved cameras")
      ->capture_default_str();
  sub->add_option(
         "--frame-budget", options->frame_budget_ms,
         "Milliseconds a frame may draw while the camera moves (an octree's largest nodes, "
         "a point file's largest-looking chunks); the picture is completed once it stops "
         "(progressive refinement). 0: always draw everything")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  sub->add_option("--measurements", options->measurements_file,
                  "Measurement file (JSON): show its measurements and annotations, from its camera "
                  "unless --eye or --camera is given; the panel's Save writes it back. With --xr: "
                  "the headset's measurements are written to it when the session ends (created "
                  "if it does not exist)");
  sub->add_option("--tool", options->tool,
                  "Measurement tool a click uses: none, point, distance, height, area, angle, "
                  "profile or annotation (also in the panel)")
      ->capture_default_str();
  sub->add_option("--volume-base", options->volume_base,
                  "Base of the Volume tool (an area measurement selected, Ctrl+V): plane, lowest "
                  "or a raster file (a DTM GeoTIFF), as volume --base takes it (also in the panel)")
      ->capture_default_str();
  sub->add_option("--profile-width", options->profile_width,
                  "Corridor width of new height profiles, in the cloud's units (also in the panel)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--process-step", options->process_steps,
                  "A step of the Processing panel, as `process` takes it: \"normals 16\", "
                  "\"outliers statistical:8,2\", \"subsample voxel:0.1\", \"distance-to "
                  "REF\" (repeatable, run in order; K or the panel's Run runs them)");
  sub->add_option("--raster", options->raster,
                  "A single-band raster in the cloud's CRS (a GeoTIFF of parallax raster) drawn "
                  "with the points, coloured by --raster-ramp and shaded (the panel's Raster "
                  "layer section loads another)");
  sub->add_option("--raster-ramp", options->raster_ramp,
                  "Ramp of --raster's colours: " + colorRampNames())
      ->capture_default_str();
  sub->add_option("--register-with", options->register_with,
                  "Register the cloud to this target file (point-to-plane ICP, as parallax "
                  "register) and preview both, coloured apart, before and after; the panel's "
                  "Accept writes the transform");
  sub->add_flag("--pick-pairs", options->pick_pairs,
                "With --register-with: pick pairs of points (a click on the source, then its match "
                "on the target; three or more) for the initial transform, previewed at once; "
                "Enter then refines it by ICP");
  sub->add_option("--write-transform", options->write_transform,
                  "Where Accept writes the transform (default SOURCE-to-TARGET.txt in "
                  "--screenshot-dir), four lines of four numbers as register --init reads");
  sub->add_option("--process-output", options->process_output,
                  "Where the Processing panel writes its result (default: NAME-processed.ply in "
                  "--screenshot-dir)");
  addRenderOptions(*sub, options->render);
  addLodOptions(*sub, options->lod);
  sub->add_flag("--xr", options->xr,
                std::string("Show the cloud in an OpenXR headset (the runtime XR_RUNTIME_JSON or "
                            "the active one names) instead of a window") +
                    (xrViewAvailable() ? "" : "; not in this build"));
  sub->add_option("--xr-origin", options->xr_options.origin,
                  "The file coordinate X,Y,Z put at the stage's origin (default: the centre of "
                  "the cloud's base)")
      ->delimiter(',')
      ->expected(3);
  sub->add_option("--xr-scale", options->xr_options.scale,
                  "Stage metres per file unit (default 1: true scale); stage = ((X-Ox)*S, "
                  "(Z-Oz)*S, -(Y-Oy)*S)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--xr-tabletop", options->xr_options.tabletop,
                "Fit the cloud in 1 m (a tabletop model) instead of true scale");
  sub->add_flag("--xr-no-mirror", options->xr_options.no_mirror,
                "No mirror window (the left eye, --width x --height) even where DISPLAY is set: "
                "draw headless through EGL (needs the runtime's XR_MNDX_egl_enable)");
  sub->add_flag("--xr-vignette", options->xr_options.vignette,
                "Fade the edges of the view to black while flying (a comfort option)");
  sub->add_option("--xr-frames", options->xr_options.frames,
                  "End the session after N frames (0: when the runtime ends it)")
      ->check(CLI::NonNegativeNumber);
  sub->footer(
      "Unlike render, view shows surfaces by default: round points sized to the local spacing "
      "(unless --size-mode, --point-size or --shape is given), lit by the normals where the "
      "cloud has them (unless --lighting or --lighting=false is given).");
  command.subcommand = sub;
  // The first picture's time counts from here, after the option parsing (microseconds).
  command.run = [options, sub] {
    return runView(*options, *sub, std::chrono::steady_clock::now());
  };
  return command;
}

}  // namespace parallax::cli
