#include "render_options.h"

#include <algorithm>
#include <stdexcept>

namespace parallax::cli {

namespace {

std::array<float, 3> colorFrom(const std::vector<int>& rgb, const char* option) {
  if (rgb.size() != 3) {
    throw std::invalid_argument(std::string(option) + " takes R,G,B (three numbers 0-255)");
  }
  std::array<float, 3> result{};
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < 0 || rgb[i] > 255) {
      throw std::invalid_argument(std::string(option) + ": " + std::to_string(rgb[i]) +
                                  " is outside 0-255");
    }
    result[i] = float(rgb[i]) / 255.0f;
  }
  return result;
}

glm::dvec3 vectorFrom(const std::vector<double>& v, const char* option) {
  if (v.size() != 3) throw std::invalid_argument(std::string(option) + " takes X,Y,Z");
  return {v[0], v[1], v[2]};
}

}  // namespace

void addRenderOptions(CLI::App& command, RenderOptions& o) {
  command
      .add_option("--color", o.color,
                  "Colour mode: " + colorModeNames() +
                      ", or the name of a scalar attribute (distance, curvature, ...) shown "
                      "with --color-ramp")
      ->capture_default_str();
  command
      .add_option("--color-ramp", o.color_ramp,
                  "Ramp of a scalar attribute's colours: " + colorRampNames())
      ->capture_default_str();
  command
      .add_option("--color-range", o.color_range,
                  "MIN,MAX of the scalar attribute's ramp (default: from --color-percentiles); "
                  "values outside take the nearer end's colour")
      ->delimiter(',')
      ->expected(2);
  command
      .add_option("--color-percentiles", o.color_percentiles,
                  "LOW,HIGH: the automatic range of a scalar attribute's ramp runs from its "
                  "LOWth to its HIGHth percentile (0,100: smallest to largest; 2,98 leaves out "
                  "outliers); a diverging ramp's is made symmetric about zero")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  command
      .add_option("--length-unit", o.length_unit,
                  "Unit written in the legend of distances and heights (distance, "
                  "height_above_ground, m3c2_*): the cloud's length unit")
      ->capture_default_str();
  command.add_option("--point-size", o.point_size, "Point size in pixels (fixed size mode)")
      ->capture_default_str()
      ->check(CLI::Range(1.0f, 255.0f));
  command.add_option("--size-mode", o.size_mode, "Point size: fixed|attenuated|adaptive")
      ->capture_default_str();
  command.add_option("--shape", o.shape, "Point shape: square|round")->capture_default_str();
  command.add_option("--world-size", o.world_size,
                     "Point size in world units (attenuated mode; default: twice the spacing)");
  command
      .add_option("--adaptive-scale", o.adaptive_scale,
                  "Point size as a multiple of the local spacing (adaptive mode)")
      ->capture_default_str();
  command.add_option("--uniform-color", o.uniform_color, "R,G,B (0-255) of --color uniform")
      ->delimiter(',')
      ->expected(3);
  command.add_option("--background", o.background, "R,G,B (0-255)")->delimiter(',')->expected(3);
  command.add_flag("--lighting", o.lighting, "Head-light shading from normals");
  command.add_flag("--edl", o.edl, "Eye-dome lighting");
  command.add_option("--edl-strength", o.edl_strength, "Eye-dome lighting strength")
      ->capture_default_str();
  command.add_option("--edl-radius", o.edl_radius, "Eye-dome lighting radius in pixels")
      ->capture_default_str();
  command
      .add_option("--msaa", o.msaa,
                  "Multisampling: samples per pixel, 0 (off: exact pixels), 2, 4 or 8 (at most "
                  "what the GPU offers)")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1, 2, 4, 8}));
  command
      .add_option("--rasterizer", o.rasterizer,
                  "Who draws the points: points (GL_POINTS), compute (an atomic minimum per pixel "
                  "in compute shaders), auto (compute wherever it supports the settings)")
      ->capture_default_str();
  command.add_flag("--hq", o.hq,
                   "High quality: blend the points within 1% of the front-most depth per pixel "
                   "(compute rasterizer)");
  command.add_option("--eye", o.eye, "Camera position X,Y,Z (file coordinates)")
      ->delimiter(',')
      ->expected(3);
  command.add_option("--target", o.target, "Point looked at X,Y,Z (default: the cloud's centre)")
      ->delimiter(',')
      ->expected(3);
  command.add_option("--up", o.up, "Up direction X,Y,Z")->delimiter(',')->expected(3);
  command.add_option("--fov", o.fov, "Vertical field of view in degrees")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 179.0));
  command.add_flag("--ortho", o.orthographic, "Orthographic projection");
  command.add_option("--camera", o.camera_file, "Camera JSON file (as the viewer saves it)");
  command.add_option("--stereo", o.stereo, "Stereo display mode: " + stereoModeNames())
      ->capture_default_str();
  command
      .add_option("--eye-separation", o.eye_separation,
                  "Stereo eye separation in scene units (default: convergence / 30)")
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--convergence", o.convergence,
                  "Stereo convergence (zero parallax) distance in scene units (default: the "
                  "distance to the pivot, the cloud's centre)")
      ->check(CLI::NonNegativeNumber);
  command.add_flag("--swap-eyes", o.swap_eyes, "Swap the left and right eyes' pictures");
  addFilterOptions(command, o.filter, "drawn");
}

void addLodOptions(CLI::App& command, LodOptions& o) {
  command
      .add_option("--budget", o.budget,
                  "Level of detail: most points drawn a frame; files with more points are "
                  "converted to an octree (cached) and streamed")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 40));
  command
      .add_option("--min-node-size", o.min_node_size,
                  "Level of detail: octree nodes smaller than this on screen (pixels) are skipped")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command.add_option("--cache-dir", o.cache_dir,
                     "Folder for the octrees of large files (default: $XDG_CACHE_HOME/parallax/"
                     "octrees, else ~/.cache/parallax/octrees), and in DIR/http the cache of "
                     "octrees read from URLs");
  command.add_flag("--no-cache", o.no_cache,
                   "Build the octree of a large file in a temporary folder removed at exit; "
                   "keep nothing read from a URL on disk");
  command.add_option("--memory", o.memory_mb, "Memory budget in MB of an octree conversion")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t(16), std::uint64_t(1) << 24));
}

LodFrameSettings lodFrameSettingsFrom(const LodOptions& o) {
  LodFrameSettings settings;
  settings.selection.point_budget = o.budget;
  settings.selection.min_node_size_px = o.min_node_size;
  return settings;
}

OctreeCacheSettings octreeCacheSettingsFrom(const LodOptions& o) {
  OctreeCacheSettings settings;
  settings.use_cache = !o.no_cache;
  settings.cache_dir = o.cache_dir;
  settings.build.memory_bytes = o.memory_mb << 20;
  return settings;
}

ViewerLookChoice viewerLookChoiceFrom(const CLI::App& command) {
  return {.size = command.count("--size-mode") == 0 && command.count("--point-size") == 0 &&
                  command.count("--shape") == 0,
          .lighting = command.count("--lighting") == 0};
}

StereoSettings stereoSettingsFrom(const RenderOptions& o) {
  const auto mode = parseStereoMode(o.stereo);
  if (!mode) {
    throw std::invalid_argument("--stereo: unknown mode '" + o.stereo + "' (use " +
                                stereoModeNames() + ")");
  }
  StereoSettings stereo;
  stereo.mode = *mode;
  stereo.eye_separation = o.eye_separation;
  stereo.convergence = o.convergence;
  stereo.swap_eyes = o.swap_eyes;
  return stereo;
}

RenderSettings renderSettingsFrom(const RenderOptions& o, double typical_spacing) {
  RenderSettings settings;
  const auto color = parseColorMode(o.color);
  const auto ramp = parseColorRamp(o.color_ramp);
  if (!ramp) {
    throw std::invalid_argument("--color-ramp: unknown ramp '" + o.color_ramp + "' (use " +
                                colorRampNames() + ")");
  }
  if (o.color.empty()) {
    throw std::invalid_argument("--color: empty (use " + colorModeNames() +
                                " or a scalar attribute's name)");
  }
  if (!o.color_range.empty()) {
    if (o.color_range.size() != 2 || !(o.color_range[0] < o.color_range[1])) {
      throw std::invalid_argument("--color-range takes MIN,MAX with MIN below MAX");
    }
    if (color) {
      throw std::invalid_argument(
          "--color-range applies to a scalar attribute's colours, not to "
          "--color " +
          o.color);
    }
  }
  const auto size_mode = parsePointSizeMode(o.size_mode);
  if (!size_mode) {
    throw std::invalid_argument("--size-mode: unknown mode '" + o.size_mode +
                                "' (use fixed|attenuated|adaptive)");
  }
  const auto shape = parsePointShape(o.shape);
  if (!shape) throw std::invalid_argument("--shape: '" + o.shape + "' (use square|round)");
  // Not a mode: a scalar attribute, checked against the cloud when it is uploaded.
  settings.color = color.value_or(ColorMode::Rgb);
  if (!color) {
    settings.scalar.field = o.color;
    settings.scalar.ramp = *ramp;
    if (!o.color_range.empty())
      settings.scalar.range = ScalarRange{o.color_range[0], o.color_range[1]};
    if (o.color_percentiles.size() != 2 || !(o.color_percentiles[0] >= 0.0) ||
        !(o.color_percentiles[1] <= 100.0) || !(o.color_percentiles[0] < o.color_percentiles[1])) {
      throw std::invalid_argument("--color-percentiles takes LOW,HIGH with 0 <= LOW < HIGH <= 100");
    }
    settings.scalar.percentiles = {o.color_percentiles[0], o.color_percentiles[1]};
  }
  settings.size_mode = *size_mode;
  settings.shape = *shape;
  settings.point_size_px = o.point_size;
  settings.world_size = o.world_size > 0 ? o.world_size : float(2.0 * typical_spacing);
  settings.adaptive_scale = o.adaptive_scale;
  settings.uniform_color = colorFrom(o.uniform_color, "--uniform-color");
  settings.background = colorFrom(o.background, "--background");
  settings.lighting = o.lighting;
  settings.edl = o.edl;
  settings.edl_strength = o.edl_strength;
  settings.edl_radius_px = o.edl_radius;
  settings.samples = o.msaa;
  const auto rasterizer = parseRasterizerKind(o.rasterizer);
  if (!rasterizer) {
    throw std::invalid_argument("--rasterizer: unknown rasterizer '" + o.rasterizer +
                                "' (use points|compute|auto)");
  }
  settings.rasterizer = *rasterizer;
  settings.hq = o.hq;
  settings.filter = pointFilterFrom(o.filter, FilterTarget::Gpu);
  return settings;
}

Camera cameraFrom(const RenderOptions& o, const ViewExtent& extent, double aspect) {
  if (!o.camera_file.empty()) return loadCamera(o.camera_file);
  const Bounds3& bounds = extent.bounds;
  Camera camera;
  camera.fov_y_deg = o.fov;
  camera.projection = o.orthographic ? Projection::Orthographic : Projection::Perspective;
  if (o.eye.empty()) {
    camera.orientation = defaultCameraFor(bounds, aspect).orientation;
    camera.world_up = vectorFrom(o.up, "--up");
    fitCamera(camera, extent, aspect);
    if (!o.target.empty()) {
      // The default direction and distance, centred on the given target.
      const glm::dvec3 shift = vectorFrom(o.target, "--target") - camera.pivot;
      camera.position += shift;
      camera.pivot += shift;
    }
    return camera;
  }
  const auto center = bounds.center();
  const glm::dvec3 target = o.target.empty() ? glm::dvec3(center[0], center[1], center[2])
                                             : vectorFrom(o.target, "--target");
  camera.lookAt(vectorFrom(o.eye, "--eye"), target, vectorFrom(o.up, "--up"));
  // Orthographic from an eye: show the whole cloud's width at the target.
  const auto size = bounds.size();
  camera.ortho_height = std::max({size[0], size[1], size[2], 1e-3});
  return camera;
}

AttributeSelection attributesDrawn(const RenderOptions& o) {
  return attributesDrawn(renderSettingsFrom(o, 0.0));
}

}  // namespace parallax::cli
