// parallax.render and parallax.pick: the picture `parallax render` writes, as a numpy array, and
// the point `parallax pick` reports, headless (EGL), through the command line's own library
// (apps/parallax/render_scene.h: the same opening, upload, camera and draw set).
//
// The options are the commands' own: keyword arguments become their command-line spelling
// (size_mode="adaptive" is --size-mode adaptive, eye=(x, y, z) is --eye x,y,z, edl=True is --edl)
// and are parsed by the registration the commands use (addRenderOptions, addLodOptions), so the
// defaults, the checks and the messages cannot drift from the command line's.
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "command_words.h"
#include "network_options.h"
#include "python_module.h"
#include "render/gl_context.h"
#include "render/point_picker.h"
#include "render/renderer.h"
#include "render_options.h"
#include "render_scene.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

// What render and pick take beyond the source: the commands' options.
struct SceneOptions {
  int width = 1280, height = 720;  // `parallax render`'s defaults (command_render.cpp)
  bool preview = false;
  int radius = 3;  // pick only
  cli::RenderOptions render;
  cli::LodOptions lod;
};

// The commands' options from Python keyword arguments; `command` is "render" or "pick". Throws
// TypeError for an argument the command does not have and ValueError for a value it refuses,
// with the command line's message.
SceneOptions sceneOptionsFrom(const py::kwargs& kwargs, const std::string& command) {
  SceneOptions o;
  CLI::App app("parallax." + command, "parallax." + command);
  app.add_option("--width", o.width)->check(CLI::Range(1, 16384));
  app.add_option("--height", o.height)->check(CLI::Range(1, 16384));
  app.add_flag("--preview", o.preview);
  if (command == "pick") app.add_option("--radius", o.radius)->check(CLI::Range(0, 64));
  cli::addRenderOptions(app, o.render);
  cli::addLodOptions(app, o.lod);

  std::vector<std::string> words;
  appendOptionWords(app, kwargs, command, words);
  std::reverse(words.begin(), words.end());  // CLI11 takes a vector last word first
  try {
    app.parse(words);
  } catch (const CLI::ParseError& error) {
    throw py::value_error(command + ": " + error.what());
  }
  return o;
}

// The source of a picture: a path or URL opened as `parallax render` opens it, or a PointCloud
// (copied: the colour modes paint the copy, and the GPU takes it).
cli::RenderSource openSource(const py::object& input, const SceneOptions& o, bool for_pick) {
  cli::RenderSource source;
  if (py::isinstance<CloudHandle>(input)) {
    const CloudPtr handle = input.cast<CloudPtr>();
    py::gil_scoped_release release;
    cli::pointFilterFrom(o.render.filter, cli::FilterTarget::Gpu);
    source.cloud = handle->cloud.clone();
    return source;
  }
  const std::string path = py::str(py::module_::import("os").attr("fspath")(input));
  py::gil_scoped_release release;
  cli::configureNetworkFrom(o.lod);
  cli::pointFilterFrom(o.render.filter, cli::FilterTarget::Gpu);  // before the file is read
  // Render reads the attributes the picture needs; pick every one (it reports the point whole).
  source = cli::openRenderSource(
      {.input = path,
       .preview = o.preview,
       .quiet = true,
       .command = for_pick ? "pick" : "render",
       .attributes = for_pick ? AttributeSelection{} : cli::attributesDrawn(o.render)},
      o.lod);
  return source;
}

// One headless frame drawn as `parallax render` draws it, handed to `use` while the GL context,
// the renderer and the target are alive (pick reads the frame back through them).
struct DrawnFrame {
  Renderer& renderer;
  RenderTarget& target;
  const DrawSet& draw_set;
  const StereoFrame& frame;
  const RenderSettings& settings;
};

template <class Use>
void drawHeadless(cli::RenderSource& source, const SceneOptions& o, bool for_pick,
                  const char* command, Use&& use) {
  // The context outlives every GL object below (declared first, destroyed last).
  const auto context = GlContext::createHeadless();
  cli::RenderScene scene = cli::uploadRenderSource(source, for_pick);
  const StereoSettings stereo = cli::headlessStereoSettings(o.render, true, command);
  const Camera camera = cli::cameraFrom(o.render, scene.extent, double(o.width) / o.height);
  const StereoFrame frame = stereoFrame(camera, stereo, o.width, o.height);
  const DrawSet& draw_set = cli::frameDrawSet(scene, source, frame, o.lod);
  const RenderSettings settings = cli::renderSettingsFrom(o.render, draw_set.typical_spacing);
  Renderer renderer;
  RenderTarget target(o.width, o.height);
  renderer.render(draw_set, frame, settings, target.framebuffer(), o.width, o.height);
  use(DrawnFrame{renderer, target, draw_set, frame, settings});
}

py::array_t<std::uint8_t> render(const py::object& input, const py::kwargs& kwargs) {
  const SceneOptions o = sceneOptionsFrom(kwargs, "render");
  cli::RenderSource source = openSource(input, o, false);
  std::vector<std::uint8_t> rgba;
  {
    py::gil_scoped_release release;
    cli::paintScalarColors(source, o.render, true, "render");
    drawHeadless(source, o, false, "render",
                 [&](const DrawnFrame& drawn) { rgba = drawn.target.readRgba(); });
  }
  py::array_t<std::uint8_t> image({py::ssize_t(o.height), py::ssize_t(o.width), py::ssize_t(3)});
  std::uint8_t* out = image.mutable_data();
  const std::size_t pixels = std::size_t(o.width) * std::size_t(o.height);
  for (std::size_t i = 0; i < pixels; ++i) {
    out[3 * i] = rgba[4 * i], out[3 * i + 1] = rgba[4 * i + 1], out[3 * i + 2] = rgba[4 * i + 2];
  }
  return image;
}

// Whole numbers as ints (a classification of 2, not 2.0), as `parallax pick --json` prints them;
// positions stay floats.
py::object attributeValue(const PointAttribute& attribute) {
  const bool position = attribute.name == "x" || attribute.name == "y" || attribute.name == "z";
  const double v = attribute.value;
  if (!position && std::isfinite(v) && std::floor(v) == v && std::fabs(v) < 9.0e15) {
    return py::int_(std::int64_t(v));
  }
  return py::float_(v);
}

py::dict pick(const py::object& input, const std::pair<int, int>& pixel, const py::kwargs& kwargs) {
  const SceneOptions o = sceneOptionsFrom(kwargs, "pick");
  // Plain names, not a structured binding: the lambda below captures them (clang before 16
  // cannot).
  const int pixel_x = pixel.first, pixel_y = pixel.second;
  if (pixel_x < 0 || pixel_y < 0 || pixel_x >= o.width || pixel_y >= o.height) {
    throw py::value_error("pixel (" + std::to_string(pixel_x) + ", " + std::to_string(pixel_y) +
                          "): outside the " + std::to_string(o.width) + "x" +
                          std::to_string(o.height) + " picture (x 0-" +
                          std::to_string(o.width - 1) + ", y 0-" + std::to_string(o.height - 1) +
                          "; see width and height)");
  }
  cli::RenderSource source = openSource(input, o, true);
  std::optional<PickResult> picked;
  {
    py::gil_scoped_release release;
    drawHeadless(source, o, true, "pick", [&](const DrawnFrame& drawn) {
      const auto pick_source = source.lod() ? std::make_unique<PickSource>(*source.octree)
                                            : std::make_unique<PickSource>(source.cloud);
      PickRequest request;
      request.x = pixel_x, request.y = o.height - 1 - pixel_y;  // GL counts rows from the bottom
      request.radius_px = o.radius;
      request.last_frame_matches = true;
      picked = pickPoint(drawn.renderer, *pick_source, drawn.draw_set, drawn.frame.views,
                         drawn.frame.composition, drawn.settings, o.width, o.height, request);
    });
  }
  py::dict result;
  result["found"] = picked.has_value();
  if (!picked) return result;
  py::dict point;
  for (const PointAttribute& attribute : picked->attributes) {
    point[py::str(attribute.name)] = attributeValue(attribute);
  }
  result["point"] = point;
  result["view"] = picked->view;
  result["pixel"] = py::make_tuple(pixel_x, pixel_y);
  result["point_pixel"] = py::make_tuple(picked->pixel_x, o.height - 1 - picked->pixel_y);
  result["distance_px"] = picked->distance_px;
  return result;
}

}  // namespace

void bindRender(py::module_& m) {
  m.def("render", &render, py::arg("source"),
        R"doc(The picture `parallax render SOURCE` writes, as an (height, width, 3) uint8 array.

source: a path or http(s) URL (any point file, a Potree 2.0 directory, a COPC file; a file over
budget is converted to a cached octree first, as the command does), or a PointCloud.
Keyword arguments are the command's options, with _ for -: width=1280, height=720, eye=(x, y, z),
target=, up=, fov=, ortho=, stereo="mono"|"sbs"|"top-bottom"|"anaglyph"|..., size_mode=,
point_size=, shape=, color="rgb"|"intensity"|"classification"|"elevation"|ATTRIBUTE, color_ramp=,
color_range=, background=, edl=, msaa=, rasterizer=, classes=, clip_box=, budget=, preview=, ...
with the same defaults. Headless (EGL); the GIL is released while it loads and draws.)doc");
  m.def("pick", &pick, py::arg("source"), py::arg("pixel"),
        R"doc(The point `parallax pick SOURCE --pixel X,Y --json` reports: a dict of found, point
(every attribute by name), view, pixel, point_pixel and distance_px (only found where none is).

pixel: (x, y) from the left and the top of the picture render() makes with the same keyword
arguments (and radius=3: where no point covers the pixel, the nearest drawn within it).)doc");
}

}  // namespace parallax::python
