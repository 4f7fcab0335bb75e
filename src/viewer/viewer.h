// `parallax view`: a window (GLFW, OpenGL 4.5 core) showing one point cloud, with mouse and
// keyboard camera control and an on-screen panel (Dear ImGui) for every render setting.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "lod/octree_cache.h"
#include "measure/measurement_document.h"
#include "render/camera.h"
#include "render/lod_scene.h"
#include "render/render_settings.h"
#include "render/stereo.h"
#include "render/view_extent.h"
#include "viewer/measure_tool.h"

namespace parallax {

struct ViewerOptions {
  std::filesystem::path input;  // may be empty: an empty window that accepts a dropped file
  RenderSettings settings;
  // Quad-buffer asks the window for a stereo (GL_STEREO) visual; where the display has none,
  // the viewer says so and shows sbs instead.
  StereoSettings stereo;
  // The first camera for a cloud with this extent (bounds and a sample of points), at this aspect
  // ratio; empty: the default direction fitted to the points as they project.
  std::function<Camera(const ViewExtent&, double aspect)> initial_camera;
  // initial_camera fits the extent (no camera given by the user): the viewer fits it again, its
  // direction kept, into the part of the window right of the panel. False: used as it comes.
  bool initial_camera_fits = true;
  // A look that shows surfaces, chosen for each cloud opened (the `view` command asks for it
  // unless the user chose the size, shape or lighting): round points sized to the local spacing
  // (`settings.size_mode` adaptive, `shape` round) where the spacing is known, and lit by their
  // normals (`settings.lighting`) where the cloud has normals.
  bool choose_size = false;
  bool choose_lighting = false;
  int width = 1280, height = 720;
  bool vsync = true;
  std::filesystem::path screenshot_dir = ".";  // where the screenshot key (P) writes PNGs
  std::string title = "Parallax";
  // Level of detail: the point budget and minimum node size (live in the panel and on the , and
  // . keys), and where the octrees of files over the budget are built.
  LodFrameSettings lod;
  OctreeCacheSettings cache;
  // Progressive refinement of level-of-detail frames (render/progressive.h): while the camera
  // moves, a frame draws the most important nodes that fit this many milliseconds; once it stops,
  // the rest is drawn on top, a budget at a time. 0: every frame draws everything it selected.
  // Live in the panel.
  double frame_budget_ms = 1000.0 / 15.0;
  // Measurements: the tool a click uses at first, the document shown at first (its camera is
  // the caller's to use, through initial_camera), and the file the panel saves to and loads.
  MeasureTool measure_tool = MeasureTool::None;
  double profile_width = 1.0;  // the corridor width of new profiles (world units, > 0)
  MeasurementDocument measurements;
  std::filesystem::path measurements_file;
  // The Volume tool's base at first, as `parallax volume --base` takes it (raster/volume.h
  // setVolumeBase): plane, lowest or a raster file's path (also in the panel).
  std::string volume_base = "plane";
  // The Processing panel's steps at first, one a line as process/process_steps.h
  // parseProcessStep reads them ("normals 16"), and the file its result is written to (empty:
  // NAME-processed.ply in screenshot_dir).
  std::vector<std::string> process_steps;
  std::filesystem::path process_output;
  // A raster drawn with the cloud (raster/raster_layer.h), coloured by `raster_ramp`; empty:
  // none (the panel can load one).
  std::filesystem::path raster;
  ColorRamp raster_ramp = ColorRamp::Viridis;
  // The registration preview: the target file the cloud shown is registered to at once (ICP,
  // registration/cloud_registration.h; empty: none, the panel can start one) and where the
  // panel's Accept writes the transform.
  std::filesystem::path register_with;
  std::filesystem::path write_transform;
  // With register_with: pick pairs of points (source, then target) for the initial transform
  // instead of running ICP at once; Enter (or the panel's Refine) then runs ICP from it.
  bool pick_pairs = false;
  // The unit the legend of distances and heights shows (render/scalar_legend.h fieldUnit).
  std::string length_unit = "m";
  // When the command started: the time to the first picture is printed from here.
  std::chrono::steady_clock::time_point start_time = std::chrono::steady_clock::now();
};

// Opens the window and runs until it is closed or Escape is pressed; returns the exit status.
//
// What it opens: a point file within the point budget is uploaded whole. A Potree 2.0 directory
// is streamed through a LodScene. A PLY, LAS or text file over the budget opens its cached octree
// at once when there is one; otherwise the viewer shows an even sample of the file (PLY; LAS and
// text show nothing until the octree is ready), builds the octree on a background thread (progress in the
// panel) and then switches to it without moving the camera. Quitting during a build ends the
// process at once, removing what the conversion had written.
// A file that cannot be read is reported in the panel and on stderr, never a crash. Throws
// std::runtime_error when no window or no 4.5 context can be created (no display, old driver).
int runViewer(const ViewerOptions& options);

}  // namespace parallax
