// The render settings and camera options shared by `parallax render` and `parallax view`.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "filter_options.h"
#include "lod/octree_cache.h"
#include "render/camera.h"
#include "render/lod_scene.h"
#include "render/render_settings.h"
#include "render/stereo.h"
#include "render/view_extent.h"

namespace parallax::cli {

struct RenderOptions {
  std::string color = "rgb";  // a colour mode, or the name of a scalar attribute
  std::string color_ramp = "viridis";
  std::vector<double> color_range;  // MIN,MAX; empty: automatic, from color_percentiles
  std::vector<double> color_percentiles{0.0, 100.0};  // LOW,HIGH percentiles of the auto range
  std::string length_unit = "m";                      // the legend's unit of distances and heights
  std::string size_mode = "fixed";
  std::string shape = "square";
  float point_size = 1.0f;
  float world_size = 0.0f;  // 0: twice the cloud's typical spacing
  float adaptive_scale = 1.5f;
  std::vector<int> uniform_color{255, 255, 255};
  std::vector<int> background{0, 0, 0};
  bool lighting = false;
  bool edl = false;
  float edl_strength = 1.0f;
  float edl_radius = 1.4f;
  int msaa = 0;
  std::string rasterizer = "auto";
  bool hq = false;
  std::vector<double> eye, target, up{0.0, 0.0, 1.0};
  double fov = 60.0;
  bool orthographic = false;
  std::string camera_file;
  std::string stereo = "mono";
  double eye_separation = 0.0;  // 0: automatic (convergence / 30)
  double convergence = 0.0;     // 0: automatic (the pivot's depth)
  bool swap_eyes = false;
  FilterOptions filter;  // --classes, --clip-box, --clip-mode
};

// Level of detail, for a Potree directory and for files with more points than the budget.
struct LodOptions {
  std::uint64_t budget = NodeSelectionSettings{}.point_budget;
  double min_node_size = NodeSelectionSettings{}.min_node_size_px;
  std::string cache_dir;  // empty: the user's cache folder (lod/octree_cache.h)
  bool no_cache = false;
  std::uint64_t memory_mb = 2048;
};

// Registers --budget, --min-node-size, --cache-dir, --no-cache, --memory.
void addLodOptions(CLI::App& command, LodOptions& options);
LodFrameSettings lodFrameSettingsFrom(const LodOptions& options);
OctreeCacheSettings octreeCacheSettingsFrom(const LodOptions& options);

// Registers --color, --color-ramp, --color-range, --color-percentiles, --length-unit,
// --point-size, --size-mode, --shape, --world-size, --adaptive-scale,
// --uniform-color, --background, --lighting, --edl, --edl-strength, --edl-radius, --msaa,
// --rasterizer, --hq, --eye,
// --target, --up, --fov, --ortho, --camera, --stereo, --eye-separation, --convergence,
// --swap-eyes, --classes, --clip-box, --clip-mode.
void addRenderOptions(CLI::App& command, RenderOptions& options);

// Validated settings; throws std::invalid_argument naming the option and its allowed values.
RenderSettings renderSettingsFrom(const RenderOptions& options, double typical_spacing);

// The attributes a picture with these options needs: positions, what the colour mode shows
// (colour, intensity, classification or a scalar attribute) and what the filters test (classes,
// returns, intensity, GPS time). A LAZ or COPC input reads only those (core/attribute_selection.h).
// Throws as renderSettingsFrom does.
AttributeSelection attributesDrawn(const RenderOptions& options);

// What the viewer's look (render_settings.h viewerLook) may choose after `command` parsed
// addRenderOptions: the size unless --size-mode, --point-size or --shape was given, the lighting
// unless --lighting was (either way). `parallax view` and `bench render --look viewer`.
ViewerLookChoice viewerLookChoiceFrom(const CLI::App& command);

// Validated stereo settings (automatic values left at 0); throws std::invalid_argument naming the
// option and its allowed values.
StereoSettings stereoSettingsFrom(const RenderOptions& options);

// The camera: --camera FILE, else --eye/--target/--up/--fov, else the default direction fitted
// to the extent's points as they project (render/view_extent.h).
Camera cameraFrom(const RenderOptions& options, const ViewExtent& extent, double aspect);

}  // namespace parallax::cli
