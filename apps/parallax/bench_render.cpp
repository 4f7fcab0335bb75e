// `parallax bench render [INPUT] [--look render|viewer] [--orbit N] [--json] [LOOK OPTIONS]`:
// the renderer's frame times beside a same-run reference.
//
// INPUT, a point file (PLY, LAS, LAZ, text): opened as `parallax render` opens it
// (render_scene.h: a file over --budget through its octree, below), drawn whole every frame with
// the look of the options (every look option of `view` and `render`: --size-mode, --shape,
// --point-size, --lighting, --edl, --color, the filters, --stereo MODE, --rasterizer, ...).
// `--look viewer` gives what `parallax view` shows for that cloud (render_settings.h viewerLook:
// round points sized to the local spacing, lit where the cloud has normals, unless the options
// say otherwise); the default `--look render` reads the options as `render` does (1-pixel
// squares, unlit). `--orbit N`: N frames of the camera turning around the cloud's centre
// (2 degrees a frame), without it --repeat frames from the still default camera. Each frame is
// interleaved with a reference (bench_render_orbit.h: the same look drawn by GL_POINTS where
// compute drew, else 1-pixel unlit squares): a table of median, p90 and worst frame times and the
// ratio, or with --json one object (median_ms, p90_ms, worst_ms, settings, rasterizer, atomic64,
// reference, ratio, load_average). `--no-atomic64`: the compute rasterizer's 32-bit path even
// where GL_NV_shader_atomic_int64 is offered.
//
// INPUT, a Potree directory or COPC file (or its URL): level of detail (bench_render_lod.cpp),
// a frame beside the same points drawn plainly, or with --orbit the viewer's streaming orbit.
//
// Without INPUT: `[--points N] [--width W] [--height H] [--repeat R] [--order
// morton|random|both]`, the throughput of N random points:
//
// --rasterizer points: the renderer with GL_POINTS beside a bare GL_POINTS loop (below).
// --rasterizer compute (auto: compute wherever it supports the settings): the renderer with the
// compute rasterizer beside the renderer with GL_POINTS, frames interleaved one by one so that a
// change in the machine's load hits both alike; "compute / points" is the speed-up.
// With --json, one JSON object on stdout (Morton order unless --order says otherwise):
// points_per_second is the median rate of the chosen rasterizer, `reference` the same-run
// reference's, `ratio` theirs, `cpu_ms` the process CPU time per frame (what a loaded machine
// does not distort as much as the wall clock), `load_average` /proc/loadavg before and after.
//
// The scene: N random points filling a box that fills the view, with colours. Both sides draw the
// same points into a framebuffer of the same size (RGBA8 colour, float depth, depth test) and are
// timed to glFinish, median of R frames after one warm-up frame:
//   reference  one buffer of interleaved vec3 float + rgba8, a shader that only transforms and
//              passes the colour through, gl_PointSize 1, one draw call;
//   renderer   Renderer::render: chunked buffers, chunk-relative positions, the full point shader
//              (the look options: --color rgb, fixed 1-pixel points by default), frustum
//              culling, and the copy into the target.
// Both are measured with the points in file (random) order and in Morton order, since llvmpipe's
// tile cache makes the order matter more than anything the shader does.
//
// `--stereo MODE` (repeatable): the renderer on the Morton-ordered cloud in mono and in that
// stereo mode, in the same run, at the same output size (--width x --height is the whole output,
// as in `parallax render`), and the ratio stereo / mono: what stereo costs. Beside them, the
// mono frame drawn twice in a row: what a second eye's rasterization alone costs, so that
// stereo / (2 x mono) above 1 is work the stereo path adds.
//
// `--filter-toggle [--returns ...]`: what toggling a point filter costs (bench_render_filter.h).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <glm/gtc/type_ptr.hpp>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>
#include "bench_render_filter.h"
#include "bench_render_lod.h"
#include "bench_render_orbit.h"
#include "bench_timing.h"
#include "commands.h"
#include "core/point_cloud.h"
#include "io/point_format.h"
#include "lod/octree_open.h"
#include "lod/octree_url.h"
#include "network_options.h"
#include "render/gl_context.h"
#include "render/point_buffers.h"
#include "render/renderer.h"
#include "render/shader_program.h"
#include "render/stereo.h"
#include "render/view_extent.h"
#include "render_options.h"
#include "render_scene.h"
#include "viewer/viewer.h"

namespace parallax::cli {
namespace {

struct RenderBenchOptions {
  std::string input;  // a point file, Potree directory or COPC file; empty: random points
  std::uint64_t points = 4'000'000;
  int width = 1920, height = 1080;
  int repeat = 5;
  std::vector<std::string> stereo;  // random points, octree: modes to compare with mono
  std::string order;                // morton|random|both; empty: both, or morton with --json
  bool json = false;
  int orbit_frames = 0;         // an orbit of this many frames (0: none)
  double frame_budget_ms = 0;   // an --orbit's progressive refinement budget (0: none)
  bool filter_toggle = false;   // frames with and without the filter (bench_render_filter.h)
  bool selective_load = false;  // an octree: its load with what the look draws, and with all
  std::string look = "render";
  bool no_atomic64 = false;
  bool pass_times = false;  // the compute rasterizer's passes timed apart (an octree)
  RenderOptions render;     // the look: every option of `view` and `render`
  LodOptions lod;
};

PointCloud randomCloud(std::uint64_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.positions = Column<Int3>(count);
  cloud.colors = Column<Rgba8>(count);
  std::mt19937 random(1234);
  std::uniform_int_distribution<std::int32_t> coordinate(-50'000, 50'000);  // a 100 m box
  for (std::uint64_t i = 0; i < count; ++i) {
    cloud.positions[i] = {coordinate(random), coordinate(random), coordinate(random) / 4};
    const std::uint32_t bits = random();
    cloud.colors[i] = {std::uint8_t(bits), std::uint8_t(bits >> 8), std::uint8_t(bits >> 16), 255};
  }
  cloud.computeBounds();
  return cloud;
}

const char* const kBareVertex = R"glsl(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_mvp;
out vec4 v_color;
void main() {
  gl_Position = u_mvp * vec4(a_position, 1.0);
  gl_PointSize = 1.0;
  v_color = a_color;
}
)glsl";

const char* const kBareFragment = R"glsl(#version 450 core
in vec4 v_color;
out vec4 out_color;
void main() { out_color = v_color; }
)glsl";

// The reference: what any GL_POINTS viewer must at least do.
class BarePoints {
 public:
  BarePoints(const PointCloud& cloud, const std::vector<std::uint32_t>& order, int width,
             int height)
      : program_({{GL_VERTEX_SHADER, "bench_bare.vert", kBareVertex},
                  {GL_FRAGMENT_SHADER, "bench_bare.frag", kBareFragment}}),
        count_(GLsizei(cloud.count)),
        width_(width),
        height_(height) {
    struct Vertex {
      float x, y, z;
      Rgba8 color;
    };
    std::vector<Vertex> vertices(cloud.count);
    for (std::size_t i = 0; i < cloud.count; ++i) {
      const std::size_t src = order[i];
      vertices[i] = {float(cloud.worldX(src)), float(cloud.worldY(src)), float(cloud.worldZ(src)),
                     cloud.colors[src]};
    }
    glCreateBuffers(1, &buffer_);
    glNamedBufferStorage(buffer_, GLsizeiptr(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
    glCreateVertexArrays(1, &vao_);
    glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, sizeof(Vertex));
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(vao_, 1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 12);
    glVertexArrayAttribBinding(vao_, 0, 0);
    glVertexArrayAttribBinding(vao_, 1, 0);
    glEnableVertexArrayAttrib(vao_, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    glCreateTextures(GL_TEXTURE_2D, 1, &color_);
    glTextureStorage2D(color_, 1, GL_RGBA8, width, height);
    glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
    glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &framebuffer_);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, color_, 0);
    glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
  }
  ~BarePoints() {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteTextures(1, &color_);
    glDeleteTextures(1, &depth_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(1, &buffer_);
  }

  void draw(const glm::dmat4& world_to_clip) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glViewport(0, 0, width_, height_);
    const float black[] = {0, 0, 0, 1};
    const float far_depth = 0.0f;
    glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, black);
    glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &far_depth);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_PROGRAM_POINT_SIZE);
    glPointSize(1.0f);
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("u_mvp"), 1, GL_FALSE,
                       glm::value_ptr(glm::mat4(world_to_clip)));
    glBindVertexArray(vao_);
    glDrawArrays(GL_POINTS, 0, count_);
    glBindVertexArray(0);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  }

 private:
  ShaderProgram program_;
  GLsizei count_;
  int width_, height_;
  GLuint buffer_ = 0, vao_ = 0, color_ = 0, depth_ = 0, framebuffer_ = 0;
};

// Wall and CPU time of one frame, median of `repeat`, two sides interleaved frame by frame.
struct Timing {
  double wall_s = 0, cpu_s = 0;
};
template <class DrawA, class DrawB>
std::pair<Timing, Timing> interleaved(int repeat, DrawA a, DrawB b) {
  a(), b(), glFinish();  // warm-up: shaders, buffers, the first touch of the framebuffer
  std::vector<double> wall[2], cpu[2];
  for (int i = 0; i < repeat; ++i) {
    for (int side = 0; side < 2; ++side) {
      const auto start = Clock::now();
      const double cpu_start = processCpuSeconds();
      side == 0 ? a() : b();
      glFinish();
      wall[side].push_back(std::chrono::duration<double>(Clock::now() - start).count());
      cpu[side].push_back(processCpuSeconds() - cpu_start);
    }
  }
  return {{median(wall[0]), median(cpu[0])}, {median(wall[1]), median(cpu[1])}};
}

// Mono and each stereo mode, interleaved frame by frame so that a change in the machine's load
// (other processes on a shared machine) hits both sides alike.
nlohmann::json benchStereo(const RenderBenchOptions& o, const PointCloud& cloud,
                           const Camera& camera, const RenderSettings& settings,
                           const std::vector<StereoMode>& modes) {
  nlohmann::json results = nlohmann::json::array();
  GpuPointCloud gpu(cloud);
  const DrawSet draw_set = gpu.drawSet();
  RenderTarget target(o.width, o.height);
  // One renderer each: the composed modes' canvas is twice as wide, and one renderer alternating
  // between the sizes would reallocate its framebuffers every frame.
  const ComputeRasterizerOptions compute{.allow_64bit_atomics = !o.no_atomic64};
  Renderer mono_renderer(compute), stereo_renderer(compute);
  for (const StereoMode mode : modes) {
    StereoSettings stereo;
    stereo.mode = mode;
    const StereoFrame mono = stereoFrame(camera, {}, o.width, o.height);
    const StereoFrame frame = stereoFrame(camera, stereo, o.width, o.height);
    std::vector<double> mono_times, twice_times, stereo_times;
    auto timed = [&](const StereoFrame& f, int frames) {
      Renderer& renderer = f.views.size() == 1 ? mono_renderer : stereo_renderer;
      const auto start = Clock::now();
      for (int i = 0; i < frames; ++i) {
        renderer.render(draw_set, f, settings, target.framebuffer(), o.width, o.height);
      }
      glFinish();
      return std::chrono::duration<double>(Clock::now() - start).count();
    };
    timed(mono, 1), timed(frame, 1);  // warm-up: shaders, framebuffers of both sizes
    for (int i = 0; i < o.repeat; ++i) {
      mono_times.push_back(timed(mono, 1));
      twice_times.push_back(timed(mono, 2));
      stereo_times.push_back(timed(frame, 1));
    }
    const double mono_s = median(mono_times), twice_s = median(twice_times);
    const double stereo_s = median(stereo_times);
    results.push_back({{"mode", stereoModeName(mode)},
                       {"mono_ms", mono_s * 1e3},
                       {"two_mono_ms", twice_s * 1e3},
                       {"stereo_ms", stereo_s * 1e3},
                       {"stereo_over_mono", stereo_s / mono_s}});
    if (o.json) continue;
    std::printf(
        "stereo %-15s mono %6.1f ms  2 x mono %6.1f ms  stereo %6.1f ms  stereo / mono %.2f  "
        "stereo / (2 x mono) %.2f\n",
        std::string(stereoModeName(mode)).c_str(), mono_s * 1e3, twice_s * 1e3, stereo_s * 1e3,
        stereo_s / mono_s, stereo_s / twice_s);
  }
  return results;
}

std::vector<StereoMode> stereoModesFrom(const RenderBenchOptions& o) {
  std::vector<StereoMode> modes;
  for (const std::string& name : o.stereo) {
    const auto mode = parseStereoMode(name);
    if (!mode) {
      throw std::invalid_argument("--stereo: '" + name + "' is not a stereo mode (use " +
                                  stereoModeNames() + ")");
    }
    // Mono is what every run measures anyway: the baseline of the comparisons, the orbit's
    // default.
    if (*mode == StereoMode::Mono) continue;
    if (*mode == StereoMode::QuadBuffer) {
      if (!o.json) {
        std::printf(
            "quad-buffer needs a stereo window, headless has none: measuring sbs instead\n");
      }
      modes.push_back(StereoMode::SideBySide);
    } else {
      modes.push_back(*mode);
    }
  }
  return modes;
}

// The settings of the look options, with the viewer's choice on top for --look viewer (what
// `parallax view` shows for a cloud with these traits).
RenderSettings lookSettings(const RenderBenchOptions& o, const CLI::App& command,
                            double typical_spacing, LookTraits traits) {
  const RenderSettings asked = renderSettingsFrom(o.render, typical_spacing);
  if (o.look == "render") return asked;
  return viewerLook(asked, asked, viewerLookChoiceFrom(command), traits);
}

// A point file (or an octree) opened as `parallax render` opens it, then its orbit (a file:
// bench_render_orbit.h; an octree: bench_render_lod.h).
int runBenchRenderInput(const RenderBenchOptions& o, const CLI::App& command,
                        const std::vector<StereoMode>& modes) {
  configureNetworkFrom(o.lod);
  checkOctreeUrl(o.input);
  RenderOptions render = o.render;
  // An orbit (or a still file) draws one stereo mode; without an orbit an octree compares each.
  const bool one_view_mode = o.orbit_frames > 0 || !isOctreePath(o.input);
  if (one_view_mode && modes.size() > 1) {
    throw std::invalid_argument("--stereo: an orbit draws one stereo mode, " +
                                std::to_string(modes.size()) + " were given");
  }
  if (one_view_mode && !modes.empty()) render.stereo = std::string(stereoModeName(modes.front()));
  const StereoSettings stereo = headlessStereoSettings(render, true, "bench render");
  const ComputeRasterizerOptions compute{.allow_64bit_atomics = !o.no_atomic64,
                                         .time_passes = o.pass_times};
  const double aspect = double(o.width) / o.height;

  RenderSource source =
      openRenderSource({.input = o.input, .quiet = o.json, .command = "bench render"}, o.lod);
  paintScalarColors(source, o.render, o.json, "bench render");
  // The viewer refines its moving frames (a point file's and an octree's) within its frame
  // budget: --look viewer measures that too, unless --frame-budget says otherwise (0: whole
  // frames).
  const double frame_budget_ms = command.count("--frame-budget") ? o.frame_budget_ms
                                 : o.look == "viewer"            ? ViewerOptions{}.frame_budget_ms
                                                                 : 0.0;
  if (source.lod()) {
    const Octree& octree = *source.octree;
    // As the viewer sizes an octree's attenuated points before any node is drawn: spacing / 4.
    const RenderSettings settings = lookSettings(
        o, command, octree.info().spacing / 8.0,
        {.spacing_known = octree.info().spacing > 0, .has_normals = octree.info().has_normals});
    return runBenchRenderLod({.directory = o.input,
                              .budget = o.lod.budget,
                              .min_node_size = o.lod.min_node_size,
                              .width = o.width,
                              .height = o.height,
                              .repeat = o.repeat,
                              .stereo = o.orbit_frames > 0 ? std::vector<StereoMode>{} : modes,
                              .settings = settings,
                              .orbit_frames = o.orbit_frames,
                              .frame_budget_ms = frame_budget_ms,
                              .orbit_stereo = stereo,
                              .camera = cameraFrom(render, viewExtentOf(octree), aspect),
                              .look = o.look,
                              .compute = compute,
                              .json = o.json,
                              .selective_load = o.selective_load},
                             *source.octree);
  }
  auto context = GlContext::createHeadless();
  RenderScene scene = uploadRenderSource(source, false);
  const RenderSettings settings = lookSettings(
      o, command, scene.whole.typical_spacing,
      {.spacing_known = scene.gpu->typicalSpacing() > 0, .has_normals = scene.gpu->hasNormals()});
  const bool orbit = o.orbit_frames > 0;
  return runBenchRenderFileOrbit({.input = o.input,
                                  .points = scene.points,
                                  .frames = orbit ? o.orbit_frames : o.repeat,
                                  .degrees_per_frame = orbit ? kOrbitDegreesPerFrame : 0.0,
                                  .width = o.width,
                                  .height = o.height,
                                  .look = o.look,
                                  .settings = settings,
                                  .stereo = stereo,
                                  .compute = compute,
                                  .json = o.json,
                                  .gl_renderer = context->renderer(),
                                  .frame_budget_ms = orbit ? frame_budget_ms : 0.0},
                                 scene.whole, cameraFrom(render, scene.extent, aspect));
}

int runBenchRender(const RenderBenchOptions& o, const CLI::App& command) {
  if (command.count("--orbit") && o.orbit_frames < 1) {
    throw std::invalid_argument("--orbit " + std::to_string(o.orbit_frames) +
                                ": an orbit needs at least 1 frame");
  }
  if (o.look != "render" && o.look != "viewer") {
    throw std::invalid_argument("--look: unknown look '" + o.look +
                                "' (use render: the options as `render` reads them, or viewer: "
                                "what `view` shows)");
  }
  if (o.orbit_frames > 0 && o.input.empty()) {
    throw std::invalid_argument(
        "--orbit needs a point file or an octree (random points only "
        "measure throughput)");
  }
  const std::vector<StereoMode> modes = stereoModesFrom(o);
  if (!o.input.empty()) return runBenchRenderInput(o, command, modes);

  // Random points: the throughput of the renderer (the look options apply; 1-pixel squares by
  // default). Their spacing is computed at upload; they have no normals.
  RenderSettings settings = lookSettings(o, command, 0.025, {.spacing_known = true});
  if (o.filter_toggle) {
    RenderSettings steady = settings;
    steady.filter = PointFilter{};  // the filter is what is toggled
    return runBenchRenderFilter({.points = o.points,
                                 .width = o.width,
                                 .height = o.height,
                                 .repeat = o.repeat,
                                 .settings = steady,
                                 .filter = settings.filter});
  }
  const std::string order = o.order.empty() ? (o.json ? "morton" : "both") : o.order;
  if (order != "morton" && order != "random" && order != "both") {
    throw std::invalid_argument("--order: '" + order + "' (use morton|random|both)");
  }
  const std::vector<double> load_before = loadAverage();
  auto context = GlContext::createHeadless();
  if (!o.json) {
    std::printf("bench render: %llu random points, %dx%d, median of %d frames, on %s (load %.1f)\n",
                static_cast<unsigned long long>(o.points), o.width, o.height, o.repeat,
                context->renderer().c_str(), load_before[0]);
  }
  const PointCloud cloud = randomCloud(o.points);
  Camera camera;
  camera.lookAt({0.0, -80.0, 60.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
  camera.fitToBounds(cloud.bounds, double(o.width) / o.height);
  const View view{camera, {0, 0, o.width, o.height}};
  RenderTarget target(o.width, o.height);
  const ComputeRasterizerOptions compute{.allow_64bit_atomics = !o.no_atomic64};
  Renderer renderer(compute), reference_renderer(compute);
  const RasterizerKind chosen =
      renderer.chooseRasterizer(settings, o.width, o.height, Composition::Direct);
  const double mpoints = double(o.points) / 1e6;

  nlohmann::json result;
  for (const bool sorted : {false, true}) {
    if ((sorted && order == "random") || (!sorted && order == "morton")) continue;
    PointUploadOptions upload;
    upload.morton_order = sorted;
    GpuPointCloud gpu(cloud, upload);
    const auto draw_ours = [&] {
      renderer.render(gpu, std::span(&view, 1), settings, target.framebuffer(), o.width, o.height);
    };
    Timing ours, reference;
    std::string reference_name;
    if (chosen == RasterizerKind::Compute) {
      // The same renderer and cloud with GL_POINTS, frame for frame beside the compute frames.
      RenderSettings points_settings = settings;
      points_settings.rasterizer = RasterizerKind::Points;
      reference_name = "points";
      std::tie(ours, reference) = interleaved(o.repeat, draw_ours, [&] {
        reference_renderer.render(gpu, std::span(&view, 1), points_settings, target.framebuffer(),
                                  o.width, o.height);
      });
    } else {
      // GL_POINTS beside a bare GL_POINTS loop over the same points.
      const std::vector<std::uint32_t> draw_order =
          sorted ? mortonOrder(cloud) : std::vector<std::uint32_t>();
      std::vector<std::uint32_t> file_order;
      if (!sorted) {
        file_order.resize(cloud.count);
        for (std::size_t i = 0; i < file_order.size(); ++i) file_order[i] = std::uint32_t(i);
      }
      BarePoints bare(cloud, sorted ? draw_order : file_order, o.width, o.height);
      const glm::dmat4 world_to_clip =
          camera.projectionMatrix(view.viewport.aspect(), camera.clipRange(cloud.bounds)) *
          camera.viewMatrix();
      reference_name = "bare GL_POINTS loop";
      std::tie(ours, reference) =
          interleaved(o.repeat, draw_ours, [&] { bare.draw(world_to_clip); });
    }
    const char* ours_name = chosen == RasterizerKind::Compute ? "compute" : "points";
    if (!o.json) {
      std::printf(
          "%-13s %-7s %7.2f M points/s (%6.1f ms, cpu %6.1f ms)  %s %7.2f M points/s (%6.1f ms, "
          "cpu %6.1f ms)  ratio %.2f (cpu %.2f)\n",
          sorted ? "morton order" : "random order", ours_name, mpoints / ours.wall_s,
          ours.wall_s * 1e3, ours.cpu_s * 1e3, reference_name.c_str(), mpoints / reference.wall_s,
          reference.wall_s * 1e3, reference.cpu_s * 1e3, reference.wall_s / ours.wall_s,
          reference.cpu_s / ours.cpu_s);
    }
    result = {{"bench", "render"},
              {"renderer", context->renderer()},
              {"points", o.points},
              {"width", o.width},
              {"height", o.height},
              {"repeat", o.repeat},
              {"order", sorted ? "morton" : "random"},
              {"rasterizer", ours_name},
              {"asked", rasterizerKindName(settings.rasterizer)},
              {"point_size", settings.point_size_px},
              {"shape", pointShapeName(settings.shape)},
              {"hq", settings.hq},
              {"atomic64", chosen == RasterizerKind::Compute &&
                               renderer.computeRasterizer().uses64BitAtomics()},
              {"allow_atomic64", !o.no_atomic64},
              {"settings", lookJson(o.look, settings, {})},
              {"frame_ms", ours.wall_s * 1e3},
              {"cpu_ms", ours.cpu_s * 1e3},
              {"points_per_second", double(o.points) / ours.wall_s},
              {"reference",
               {{"name", reference_name},
                {"frame_ms", reference.wall_s * 1e3},
                {"cpu_ms", reference.cpu_s * 1e3},
                {"points_per_second", double(o.points) / reference.wall_s}}},
              {"ratio", reference.wall_s / ours.wall_s},
              {"cpu_ratio", reference.cpu_s / ours.cpu_s}};
  }
  if (!modes.empty()) result["stereo"] = benchStereo(o, cloud, camera, settings, modes);
  result["load_average"] = {{"before", load_before}, {"after", loadAverage()}};
  if (o.json) std::printf("%s\n", result.dump().c_str());
  return 0;
}

}  // namespace

Command addBenchRenderCommand(CLI::App& bench) {
  auto options = std::make_shared<RenderBenchOptions>();
  Command command;
  CLI::App* sub = bench.add_subcommand(
      "render",
      "Frame times of the renderer: random points' throughput (compute vs GL_POINTS, or GL_POINTS "
      "vs a bare loop), or a point file or octree orbited with the viewer's look");
  command.subcommand = sub;
  sub->add_option("input", options->input,
                  "Point file (" + pointFormatNamesText() +
                      "; opened as `render` opens it: over --budget through its octree), Potree "
                      "2.0 directory or COPC file (or its http(s) URL). Without it: random points");
  sub->add_option("--points", options->points, "Without an input: random points to draw")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(200'000'000)))
      ->capture_default_str();
  sub->add_option("--width", options->width, "Framebuffer width")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  sub->add_option("--height", options->height, "Framebuffer height")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  sub->add_option("--repeat,-n", options->repeat,
                  "Timed frames (median shown); a point file without --orbit: still frames")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sub->add_option("--order", options->order,
                  "Random points' order: morton, random or both (default: both; morton with "
                  "--json)");
  sub->add_flag("--json", options->json,
                "Print one JSON object (random points: points_per_second, the median rate; an "
                "orbit: median_ms, p90_ms, worst_ms, settings, rasterizer, atomic64)");
  sub->add_option("--orbit", options->orbit_frames,
                  "A point file or octree: N frames of the camera orbiting the cloud's centre, "
                  "2 degrees a frame (an octree streamed as the viewer does); median, p90 and "
                  "worst frame times");
  sub->add_option("--frame-budget", options->frame_budget_ms,
                  "With --orbit: progressive refinement's time budget per moving frame, ms, as "
                  "the viewer draws (0: whole frames; default: the viewer's, 66.7, with --look "
                  "viewer, else 0)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--look", options->look,
                  "render: the look options as `render` reads them (1-pixel squares, unlit, by "
                  "default); viewer: what `view` shows, round points sized to the local spacing "
                  "(unless --size-mode, --point-size or --shape is given) lit where the cloud has "
                  "normals (unless --lighting is given)")
      ->capture_default_str();
  sub->add_flag("--no-atomic64", options->no_atomic64,
                "Compute rasterizer: the 32-bit path even where GL_NV_shader_atomic_int64 is "
                "offered (the JSON's atomic64 says which path drew)");
  sub->add_flag("--pass-times", options->pass_times,
                "An octree without --orbit: the compute rasterizer's passes timed apart (a "
                "glFinish after each), medians per side");
  sub->add_flag("--selective-load", options->selective_load,
                "An octree (COPC): the time to the first picture and to the whole load with its "
                "nodes read with what the look draws (as `view` reads them) and with every "
                "attribute, alternating in the same run");
  sub->add_flag("--filter-toggle", options->filter_toggle,
                "Random points: frames with and without the filter options (default --returns "
                "first), toggled every other frame: frame times and the bytes uploaded");
  // Every look option of `view` and `render` (--size-mode, --shape, --point-size, --lighting,
  // --edl, --color, the filters, --rasterizer, the camera ...) and the level of detail's; --stereo
  // is the bench's own: repeatable.
  addRenderOptions(*sub, options->render);
  sub->remove_option(sub->get_option("--stereo"));
  sub->add_option("--stereo", options->stereo,
                  "Stereo mode (" + stereoModeNames() +
                      "): random points and octrees compare mono with each mode given "
                      "(repeatable); an orbit or a point file draws in it");
  addLodOptions(*sub, options->lod);
  sub->footer(
      "Each figure comes with a same-run reference: random points beside a bare GL_POINTS loop "
      "(or, drawn by compute, beside GL_POINTS); a point file's frames interleaved with the same "
      "look drawn by GL_POINTS (where compute drew) or with 1-pixel unlit squares (where GL_POINTS "
      "drew); an octree's level-of-detail frame beside the same points drawn plainly.");
  command.run = [options, sub] { return runBenchRender(*options, *sub); };
  return command;
}

}  // namespace parallax::cli
