// `parallax render INPUT -o OUT.png`: one picture of a point file, headless (EGL), or with
// `--path FILE.json --frames N -o DIR/frame_%04d.png` a frame sequence along a camera path.
//
// With --stereo MODE, each picture is a stereo frame (render/stereo.h) of the whole --width x
// --height. quad-buffer needs a stereo window: headless, it falls back to sbs with a message.
//
// INPUT may be a Potree 2.0 directory or a COPC file (told by its content), or its http(s) URL:
// its octree is streamed through a LodScene (render/lod_scene.h) within --budget points, and
// each picture waits for every node it selects. A PLY, LAS, LAZ or text file with more points
// than --budget (lod/large_file.h) is converted to such an octree first (kept in the user's
// cache, or --cache-dir, for the next run; --no-cache: a temporary folder), unless --preview
// asks for a picture of an even sample at once (PLY, LAS, LAZ; the budget's worth of points, at
// most kPreviewPoints).
//
// With --measurements FILE (measure/measurement_document.h), the file's measurements and
// annotations are drawn over every picture (lines, markers and labels, depth-tested against the
// points: behind them, faded), and its camera is used unless --eye or --camera is given.
//
// Prints the time from start to PNG broken down into load, context, upload, draw and write, on
// stderr (stdout stays free for scripts).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "bench_timing.h"
#include "commands.h"
#include "core/error.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "core/url.h"
#include "io/ply_preview.h"
#include "io/point_file.h"
#include "lod/large_file.h"
#include "lod/octree_cache.h"
#include "lod/octree_open.h"
#include "lod/potree_reader.h"
#include "measure/measurement_document.h"
#include "measure/measurement_overlay.h"
#include "network_options.h"
#include "progress_options.h"
#include "raster/raster_layer.h"
#include "render/camera_path.h"
#include "render/draw_set_layers.h"
#include "render/gl_context.h"
#include "render/image_file.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/renderer.h"
#include "render/scalar_legend.h"
#include "render/stereo.h"
#include "render/view_extent.h"
#include "render_options.h"
#include "render_scene.h"

namespace parallax::cli {
namespace {

// Expands the one printf-style integer field (%d or %0Nd) of a frame pattern. Done by hand so
// that a user's pattern is never a printf format string.
std::string framePath(const std::string& pattern, int frame) {
  const auto percent = pattern.find('%');
  if (percent == std::string::npos) {
    throw std::invalid_argument("-o " + pattern + ": a frame sequence needs a %d or %04d field");
  }
  std::size_t end = percent + 1;
  int width = 0;
  while (end < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[end]))) {
    width = width * 10 + (pattern[end++] - '0');
  }
  if (end >= pattern.size() || pattern[end] != 'd' || pattern.find('%', end) != std::string::npos ||
      width > 12) {
    throw std::invalid_argument("-o " + pattern + ": use exactly one %d or %0Nd field");
  }
  std::string number = std::to_string(frame);
  if (int(number.size()) < width) number.insert(0, std::size_t(width) - number.size(), '0');
  return pattern.substr(0, percent) + number + pattern.substr(end + 1);
}

struct RenderCommandOptions {
  std::string input;
  std::string output;
  int width = 1280, height = 720;
  std::string path_file;
  int frames = 0;
  bool preview = false;
  bool quiet = false;  // no progress bar, no report on stderr
  std::string measurements_file;
  bool legend = false;
  std::string raster_file;  // a raster shown with the cloud (raster/raster_layer.h)
  std::string raster_ramp = "viridis";
  RenderOptions render;
  LodOptions lod;
};

int runRender(const RenderCommandOptions& o) {
  const auto start = Clock::now();
  // A malformed measurement file is reported before the point file is read.
  std::optional<MeasurementDocument> measurements;
  if (!o.measurements_file.empty()) measurements = loadMeasurementDocument(o.measurements_file);

  configureNetworkFrom(o.lod);
  pointFilterFrom(o.render.filter,
                  FilterTarget::Gpu);  // a malformed list is reported before the file is read
  RenderSource source = openRenderSource({.input = o.input,
                                          .preview = o.preview,
                                          .quiet = o.quiet,
                                          .attributes = attributesDrawn(o.render)},
                                         o.lod);
  const std::optional<ScalarRange> scalar_range =
      paintScalarColors(source, o.render, o.quiet, "render");
  if (o.legend && !scalar_range) {
    throw std::invalid_argument("--legend shows a scalar attribute's ramp: give --color ATTRIBUTE");
  }
  std::optional<ScalarLegend> legend;
  std::optional<OverlayFont> legend_font;  // the labels' font, as the viewer's panel has it
  if (o.legend) {
    legend_font.emplace();
    const RenderSettings asked = renderSettingsFrom(o.render, 0.0);
    legend = scalarLegend(asked.scalar.field, asked.scalar.ramp, *scalar_range,
                          fieldUnit(asked.scalar.field, o.render.length_unit));
  }
  PointCloud raster_points;
  if (!o.raster_file.empty()) {
    const auto ramp = parseColorRamp(o.raster_ramp);
    if (!ramp) {
      throw std::invalid_argument("--raster-ramp: unknown ramp '" + o.raster_ramp + "' (use " +
                                  colorRampNames() + ")");
    }
    raster_points =
        loadRasterLayer(o.raster_file, [r = *ramp](double t) { return rampColor(r, t); });
  }
  const double load_s = secondsSince(start);

  auto phase = Clock::now();
  auto context = GlContext::createHeadless();
  const double context_s = secondsSince(phase);

  phase = Clock::now();
  RenderScene scene = uploadRenderSource(source, false);
  const LodScene* lod = scene.lod.get();
  const std::uint64_t points = scene.points;
  std::unique_ptr<GpuPointCloud> raster_layer;
  if (raster_points.count) raster_layer = std::make_unique<GpuPointCloud>(raster_points);
  const double upload_s = secondsSince(phase);

  const StereoSettings stereo = headlessStereoSettings(o.render, o.quiet, "render");
  const double aspect = double(o.width) / o.height;
  std::vector<Camera> cameras;
  std::vector<std::string> outputs;
  if (!o.path_file.empty()) {
    if (o.frames < 1) throw std::invalid_argument("--path needs --frames N (at least 1)");
    const CameraPath path = loadCameraPath(o.path_file);
    for (int f = 0; f < o.frames; ++f) {
      cameras.push_back(path.frame(f, o.frames));
      outputs.push_back(framePath(o.output, f));
    }
    std::filesystem::create_directories(std::filesystem::path(outputs.front()).parent_path());
  } else if (measurements && measurements->camera && o.render.eye.empty() &&
             o.render.camera_file.empty()) {
    cameras.push_back(*measurements->camera);
    outputs.push_back(o.output);
  } else {
    cameras.push_back(cameraFrom(o.render, scene.extent, aspect));
    outputs.push_back(o.output);
  }

  Renderer renderer;
  if (measurements) {
    OverlayScene overlay;
    appendMeasurementOverlay(*measurements, {}, overlay);
    renderer.setOverlay(std::move(overlay));
  }
  RenderTarget target(o.width, o.height);
  double draw_s = 0, write_s = 0;
  std::uint64_t drawn = 0;
  FrameStats last_stats;
  std::optional<RenderSettings> settings;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    phase = Clock::now();
    const StereoFrame frame = stereoFrame(cameras[i], stereo, o.width, o.height);
    // The finished picture: finishLoading waits for every node this frame selects.
    const DrawSet& cloud_set = frameDrawSet(scene, source, frame, o.lod);
    const DrawSet draw_set =
        raster_layer ? withLayer(cloud_set, raster_layer->drawSet()) : cloud_set;
    if (!settings) settings = renderSettingsFrom(o.render, draw_set.typical_spacing);
    last_stats =
        renderer.render(draw_set, frame, *settings, target.framebuffer(), o.width, o.height);
    drawn = last_stats.points_drawn;
    glFinish();
    draw_s += secondsSince(phase);
    phase = Clock::now();
    RgbaImage image{o.width, o.height, target.readRgba()};
    if (legend) paintScalarLegend(image, *legend, *legend_font);
    writePng(outputs[i], image);
    write_s += secondsSince(phase);
  }
  const double total_s = secondsSince(start);
  if (o.quiet) return 0;
  if (stereo.mode != StereoMode::Mono) {
    const StereoSettings used = resolvedStereo(stereo, cameras.front());
    std::fprintf(stderr, "parallax render: stereo %s, eye separation %g, convergence %g%s\n",
                 std::string(stereoModeName(used.mode)).c_str(), used.eye_separation,
                 used.convergence, used.swap_eyes ? ", eyes swapped" : "");
  }
  // Which rasterizer drew, and why not compute where it was asked for.
  std::fprintf(stderr, "parallax render: rasterizer %s%s%s\n",
               last_stats.rasterizer == RasterizerKind::Compute ? "compute" : "points (GL_POINTS)",
               last_stats.fallback_reason.empty() ? "" : ": ", last_stats.fallback_reason.c_str());
  const std::uint64_t large_splats = last_stats.rasterizer == RasterizerKind::Compute
                                         ? renderer.computeRasterizer().largeSplatsOfLastFrame()
                                         : 0;
  if (large_splats) {
    std::fprintf(
        stderr, "parallax render: %llu splats wider than %g pixels drawn a workgroup each\n",
        static_cast<unsigned long long>(large_splats), double(ComputeRasterizer::kInlineSplatPx));
  }
  if (measurements) {
    std::fprintf(stderr, "parallax render: drew %zu measurements and %zu annotations of %s%s\n",
                 measurements->measurements.size(), measurements->annotations.size(),
                 o.measurements_file.c_str(),
                 measurements->camera && o.render.eye.empty() && o.render.camera_file.empty() &&
                         o.path_file.empty()
                     ? ", from its camera"
                     : "");
  }
  if (lod) {
    const LodStats& stats = lod->stats();
    std::fprintf(stderr,
                 "parallax render: level of detail, budget %llu: %zu nodes selected (%llu points), "
                 "%zu drawn (%llu points), GPU %.1f MB\n",
                 static_cast<unsigned long long>(o.lod.budget), stats.selected_nodes,
                 static_cast<unsigned long long>(stats.selected_points), stats.drawn_nodes,
                 static_cast<unsigned long long>(stats.drawn_points),
                 double(stats.gpu_bytes) / 1e6);
    printNetworkReport("parallax render", *source.octree, stats.drawn_points);
  }
  if (source.file_points) {
    std::fprintf(stderr, "parallax render: preview, a sample of %llu of the file's %llu points\n",
                 static_cast<unsigned long long>(points),
                 static_cast<unsigned long long>(source.file_points));
  }
  std::fprintf(stderr,
               "parallax render: %llu points (%llu drawn), %zu frame(s) %dx%d on %s (OpenGL %s, "
               "%s)\n"
               "  load %.3f s, context %.3f s, upload %.3f s, draw %.3f s, write %.3f s, "
               "total %.3f s\n  wrote %s%s\n",
               static_cast<unsigned long long>(points), static_cast<unsigned long long>(drawn),
               cameras.size(), o.width, o.height, context->renderer().c_str(),
               context->version().c_str(), context->platform().c_str(), load_s, context_s, upload_s,
               draw_s, write_s, total_s, outputs.front().c_str(), outputs.size() > 1 ? " ..." : "");
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  Command command;
  CLI::App* sub = app.add_subcommand("render", "Render a point file to a PNG, headless");
  sub->add_option(
         "input", options->input,
         "Point file (" + pointFormatNamesText() +
             "), or an octree: a Potree 2.0 directory or a COPC file (parallax convert), or its "
             "http(s) URL")
      ->required();
  sub->add_option("-o,--output", options->output,
                  "Output PNG (with --path: a pattern such as DIR/frame_%04d.png)")
      ->required();
  sub->add_option("--width", options->width, "Image width in pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  sub->add_option("--height", options->height, "Image height in pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  sub->add_option("--path", options->path_file, "Camera path JSON: render a frame sequence");
  sub->add_option("--frames", options->frames, "Frames along --path")->check(CLI::Range(1, 100000));
  sub->add_flag(
      "--preview", options->preview,
      "A " + previewFormatNamesText() +
          " file over --budget: draw an even sample (at most the budget, at most 1 M points) at "
          "once instead of converting it to an octree");
  sub->add_option("--measurements", options->measurements_file,
                  "Measurement file (JSON, as the viewer saves it): draw its measurements and "
                  "annotations, from its camera unless --eye or --camera is given");
  sub->add_option("--raster", options->raster_file,
                  "A single-band raster in the cloud's CRS (a GeoTIFF of parallax raster): drawn "
                  "with the points, a point per cell at its value's height, coloured by "
                  "--raster-ramp over its values and shaded by its hillshade");
  sub->add_option("--raster-ramp", options->raster_ramp,
                  "Ramp of --raster's colours: " + colorRampNames())
      ->capture_default_str();
  sub->add_flag("--legend", options->legend,
                "With --color ATTRIBUTE: draw the ramp's legend (bar, range, ticks, unit) at the "
                "right of the picture");
  addQuietFlag(*sub, options->quiet);
  addRenderOptions(*sub, options->render);
  addLodOptions(*sub, options->lod);
  command.subcommand = sub;
  command.run = [options] { return runRender(*options); };
  return command;
}

}  // namespace parallax::cli
