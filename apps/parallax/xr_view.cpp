#include "xr_view.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "filter_options.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "render_scene.h"
#include "xr/stage_mapping.h"
#include "xr/xr_headset.h"

namespace parallax::cli {

bool xrViewAvailable() {
  return true;
}

int runXrView(const XrViewOptions& o) {
  if (!o.origin.empty() && o.origin.size() != 3) {
    throw std::invalid_argument("--xr-origin: expected X,Y,Z (three numbers)");
  }
  if (o.scale < 0) throw std::invalid_argument("--xr-scale: must be greater than 0");
  pointFilterFrom(o.render.filter, FilterTarget::Gpu);
  RenderSource source = openRenderSource({.input = o.input, .command = "view"}, o.lod);
  paintScalarColors(source, o.render, false, "view");
  auto context = GlContext::createHeadless();
  RenderScene scene = uploadRenderSource(source, false);

  const Bounds3& bounds = scene.extent.bounds;
  StagePlacement placement = o.tabletop ? tabletopPlacement(bounds) : StagePlacement{};
  if (!o.tabletop) placement.origin = baseCentre(bounds);
  if (!o.origin.empty()) placement.origin = {o.origin[0], o.origin[1], o.origin[2]};
  if (o.scale > 0) placement.scale = o.scale;

  XrHeadset headset("parallax view");
  Renderer renderer;
  std::optional<RenderSettings> settings;
  std::unique_ptr<RenderTarget> canvas;  // both eyes, each in a viewport taller than its picture
  FrameStats last;
  const XrSessionStats stats = headset.run(
      [&](const XrFrameInfo& frame) {
        StereoFrame views;
        std::vector<EyeView> eyes;
        int rows = 0;
        for (const XrEye& eye : frame.eyes) {
          eyes.push_back(eyeView(placement, eye.fov, eye.pose, eye.viewport.x, eye.viewport.width,
                                 eye.viewport.height));
          views.views.push_back(eyes.back().view);
          rows = std::max(rows, eyes.back().view.viewport.height);
        }
        if (!canvas || canvas->width() != frame.width || canvas->height() != rows) {
          canvas = std::make_unique<RenderTarget>(frame.width, rows);
        }
        // One draw set (one LOD selection, one node cache) for both eyes, drawn in one pass.
        const DrawSet& draw_set = frameDrawSet(scene, source, views, o.lod);
        if (!settings) settings = renderSettingsFrom(o.render, draw_set.typical_spacing);
        last =
            renderer.render(draw_set, views, *settings, canvas->framebuffer(), frame.width, rows);
        for (std::size_t v = 0; v < eyes.size(); ++v) {
          const Viewport& to = frame.eyes[v].viewport;
          const int from_y = eyes[v].source_y;
          glBlitNamedFramebuffer(canvas->framebuffer(), frame.framebuffer, to.x, from_y,
                                 to.x + to.width, from_y + to.height, to.x, to.y, to.x + to.width,
                                 to.y + to.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
      },
      o.frames);
  std::fprintf(stderr,
               "parallax view --xr: %s on %s, %lld frames of 2 x %dx%d drawn (%llu points, "
               "rasterizer %s), origin %.3f,%.3f,%.3f, scale %g\n",
               stats.system.c_str(), stats.runtime.c_str(), stats.frames_drawn, stats.eye_width,
               stats.eye_height, static_cast<unsigned long long>(last.points_drawn),
               last.rasterizer == RasterizerKind::Compute ? "compute" : "points",
               placement.origin.x, placement.origin.y, placement.origin.z, placement.scale);
  return 0;
}

}  // namespace parallax::cli
