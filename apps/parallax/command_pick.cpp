// `parallax pick INPUT --pixel X,Y [--json]`: the point drawn at a pixel of the picture
// `parallax render` would write with the same options, with its coordinates at the file's
// precision and every attribute the source has (render/point_picker.h says how it is found).
//
// X counts from the left and Y from the top of that picture; in sbs stereo the right half is the
// right eye. Where no point covers the pixel, the nearest drawn within --radius pixels is given.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/column_names.h"
#include "io/point_format.h"
#include "network_options.h"
#include "render/gl_context.h"
#include "render/point_picker.h"
#include "render/renderer.h"
#include "render_options.h"
#include "render_scene.h"

namespace parallax::cli {
namespace {

struct PickCommandOptions {
  std::string input;
  std::string pixel;
  int width = 1280, height = 720;
  int radius = 3;
  bool json = false;
  bool preview = false;
  RenderOptions render;
  LodOptions lod;
};

// "X,Y": two whole numbers inside the image; throws std::invalid_argument naming --pixel.
std::pair<int, int> parsePixel(const PickCommandOptions& o) {
  const std::string usage = "--pixel " + o.pixel +
                            ": takes X,Y, two whole numbers of pixels (X from the left, Y from "
                            "the top of the picture), e.g. --pixel 640,360";
  const auto comma = o.pixel.find(',');
  if (comma == std::string::npos) throw std::invalid_argument(usage);
  auto number = [&](const std::string& text) {
    std::size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(text, &used);
    } catch (const std::exception&) {
      throw std::invalid_argument(usage);
    }
    if (used != text.size() || text.empty() || text[0] == ' ') throw std::invalid_argument(usage);
    return value;
  };
  const int x = number(o.pixel.substr(0, comma)), y = number(o.pixel.substr(comma + 1));
  if (x < 0 || y < 0 || x >= o.width || y >= o.height) {
    throw std::invalid_argument("--pixel " + o.pixel + ": outside the " + std::to_string(o.width) +
                                "x" + std::to_string(o.height) + " picture (X 0-" +
                                std::to_string(o.width - 1) + ", Y 0-" +
                                std::to_string(o.height - 1) + "; see --width and --height)");
  }
  return {x, y};
}

// Whole numbers print as such (a classification of 2, not 2.0); positions stay doubles.
nlohmann::ordered_json attributeValue(const PointAttribute& attribute) {
  const bool position = attribute.name == column_names::kX || attribute.name == column_names::kY ||
                        attribute.name == column_names::kZ;
  const double v = attribute.value;
  if (!position && std::isfinite(v) && std::floor(v) == v && std::fabs(v) < 9.0e15) {
    return std::int64_t(v);
  }
  return v;
}

int runPick(const PickCommandOptions& o) {
  const auto [pixel_x, pixel_y] = parsePixel(o);  // before the file is read
  configureNetworkFrom(o.lod);
  pointFilterFrom(o.render.filter, FilterTarget::Gpu);
  // Quiet: stdout carries the answer, and stderr stays free of progress bars.
  RenderSource source = openRenderSource(
      {.input = o.input, .preview = o.preview, .quiet = true, .command = "pick"}, o.lod);
  auto context = GlContext::createHeadless();
  RenderScene scene = uploadRenderSource(source, true);
  const StereoSettings stereo = headlessStereoSettings(o.render, true, "pick");
  const Camera camera = cameraFrom(o.render, scene.extent, double(o.width) / o.height);
  const StereoFrame frame = stereoFrame(camera, stereo, o.width, o.height);
  const DrawSet& draw_set = frameDrawSet(scene, source, frame, o.lod);
  const RenderSettings settings = renderSettingsFrom(o.render, draw_set.typical_spacing);

  Renderer renderer;
  RenderTarget target(o.width, o.height);
  renderer.render(draw_set, frame, settings, target.framebuffer(), o.width, o.height);
  std::unique_ptr<PickSource> pick_source = source.lod()
                                                ? std::make_unique<PickSource>(*source.octree)
                                                : std::make_unique<PickSource>(source.cloud);
  PickRequest request;
  request.x = pixel_x, request.y = o.height - 1 - pixel_y;  // GL counts rows from the bottom
  request.radius_px = o.radius;
  request.last_frame_matches = true;
  const std::optional<PickResult> picked =
      pickPoint(renderer, *pick_source, draw_set, frame.views, frame.composition, settings, o.width,
                o.height, request);

  const int found_x = picked ? picked->pixel_x : 0;
  const int found_y = picked ? o.height - 1 - picked->pixel_y : 0;
  if (o.json) {
    nlohmann::ordered_json out;  // in the order written: found, point (x y z first), ...
    out["found"] = picked.has_value();
    if (picked) {
      nlohmann::ordered_json point = nlohmann::ordered_json::object();
      for (const PointAttribute& attribute : picked->attributes) {
        point[attribute.name] = attributeValue(attribute);
      }
      out["point"] = point;
      out["view"] = picked->view;
      out["pixel"] = {pixel_x, pixel_y};
      out["point_pixel"] = {found_x, found_y};
      out["distance_px"] = picked->distance_px;
    }
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }
  if (!picked) {
    std::printf("no point drawn within %d pixels of %d,%d\n", o.radius, pixel_x, pixel_y);
    return 0;
  }
  std::printf("point at pixel %d,%d (%.2f pixels from %d,%d), %s\n", found_x, found_y,
              picked->distance_px, pixel_x, pixel_y,
              frame.views.size() > 1 ? (picked->view == 0 ? "left eye" : "right eye") : "mono");
  for (const PointAttribute& attribute : picked->attributes) {
    std::printf("  %-22s %s\n", attribute.name.c_str(), attributeValue(attribute).dump().c_str());
  }
  return 0;
}

}  // namespace

Command addPickCommand(CLI::App& app) {
  auto options = std::make_shared<PickCommandOptions>();
  Command command;
  CLI::App* sub = app.add_subcommand(
      "pick",
      "Print the point drawn at a pixel of the picture `render` makes, with all attributes");
  sub->add_option("input", options->input,
                  "Point file (" + pointFormatNamesText() +
                      "), or an octree: a Potree 2.0 directory or a COPC file, or its http(s) URL")
      ->required();
  sub->add_option("--pixel", options->pixel,
                  "X,Y: the pixel, from the left and from the top of the picture (sbs stereo: the "
                  "right half is the right eye)")
      ->required();
  sub->add_option("--width", options->width, "Picture width in pixels, as for render")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  sub->add_option("--height", options->height, "Picture height in pixels, as for render")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  sub->add_option("--radius", options->radius,
                  "Where no point covers the pixel: the nearest drawn within this many pixels")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  sub->add_flag("--json", options->json, "One JSON object on stdout");
  sub->add_flag("--preview", options->preview,
                "As render --preview: a file over --budget is drawn as an even sample");
  addRenderOptions(*sub, options->render);
  addLodOptions(*sub, options->lod);
  command.subcommand = sub;
  command.run = [options] { return runPick(*options); };
  return command;
}

}  // namespace parallax::cli
