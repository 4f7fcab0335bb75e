// Picking in every look: at every pixel a drawn splat covers, the pick names a point whose splat
// covers that pixel and that is front-most there, for each size mode (fixed small and large,
// attenuated, adaptive), each shape, both rasterizers and each stereo eye, against a coverage
// computed here on the CPU in double with the test's own projection of the same eye, target,
// field of view and stereo settings (support/reference_projection.h; GL's point rule: the pixels
// whose centres lie inside the point's square, or its disc). Where no splat covers a pixel, the
// pick finds nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <tuple>

#include "render/point_picker.h"
#include "render/stereo.h"
#include "render_test_support.h"
#include "support/reference_projection.h"

namespace parallax::test {
namespace {

// A wall standing on the ground, both sampled with jitter: seen from in front, the wall's splats
// cover the ground's behind them, as the demo scene's walls do.
PointCloud wallOnGround() {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  std::vector<std::array<double, 3>> world;
  for (double x = -2.0; x <= 2.0; x += 0.2) {
    for (double y = 0.0; y <= 4.0; y += 0.2) world.push_back({x + jitter(random), y, 0.0});
  }
  for (double x = -1.0; x <= 1.0; x += 0.15) {
    for (double z = 0.1; z <= 1.5; z += 0.15) {
      world.push_back({x + jitter(random), 1.0 + jitter(random), z + jitter(random)});
    }
  }
  return makeCloud(world, {0.0, 0.0, 0.0}, 1e-6);
}

// One point's splat in one view, as the GL_POINTS shader sizes and places it.
struct Splat {
  std::size_t point = 0;
  int view = 0;
  glm::dvec2 window{0.0};  // window coordinates (bottom-left origin, pixel centres at +0.5)
  double size = 0.0;       // pixels
  double depth = 0.0;      // eye depth
};

std::vector<Splat> cpuSplats(const PointCloud& cloud, const std::vector<ReferenceView>& views,
                             const RenderSettings& settings, double node_spacing,
                             double max_point_size) {
  std::vector<Splat> splats;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ReferenceView& view = views[v];
    const double pixels_per_unit = view.height / (2.0 * std::tan(view.fov_y_deg * M_PI / 360.0));
    for (std::size_t k = 0; k < cloud.count; ++k) {
      const auto projected =
          referenceProject(view, {cloud.worldX(k), cloud.worldY(k), cloud.worldZ(k)});
      if (!projected) continue;
      Splat splat;
      splat.point = k;
      splat.view = int(v);
      splat.window = projected->window;
      splat.depth = projected->depth;
      double size = settings.point_size_px;
      if (settings.size_mode != PointSizeMode::Fixed) {
        const double world_size = settings.size_mode == PointSizeMode::Attenuated
                                      ? settings.world_size
                                      : node_spacing * settings.adaptive_scale;
        size =
            std::clamp(world_size * pixels_per_unit / splat.depth,
                       std::max(double(settings.min_size_px), 1.0), double(settings.max_size_px));
      }
      splat.size = std::min(size, max_point_size);
      splats.push_back(splat);
    }
  }
  return splats;
}

enum class Cover { Outside, Inside, Unsure };

// Whether the centre of pixel (x, y) is inside the splat; Unsure within 0.05 pixels of its edge
// (float rounding and the shader's 1/256-pixel snap may put such a centre either side).
Cover covers(const Splat& splat, int x, int y, PointShape shape) {
  const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - splat.window;
  constexpr double kMargin = 0.05;
  const double half = splat.size / 2;
  if (shape == PointShape::Round) {
    const double distance = glm::length(d);
    if (std::abs(distance - half) < kMargin) return Cover::Unsure;
    return distance < half ? Cover::Inside : Cover::Outside;
  }
  const double edge = std::max(std::abs(d.x), std::abs(d.y));
  if (std::abs(std::abs(d.x) - half) < kMargin || std::abs(std::abs(d.y) - half) < kMargin) {
    return edge > half + kMargin ? Cover::Outside : Cover::Unsure;
  }
  return edge < half ? Cover::Inside : Cover::Outside;
}

struct Look {
  std::string name;
  RenderSettings settings;
};

std::vector<Look> everyLook() {
  std::vector<Look> looks;
  for (const PointShape shape : {PointShape::Square, PointShape::Round}) {
    const std::string shape_name(pointShapeName(shape));
    RenderSettings base;
    base.shape = shape;
    base.lighting = true;
    base.edl = true;
    base.max_size_px = 255.0f;
    RenderSettings small = base;
    small.point_size_px = 5.0f;
    RenderSettings large = base;
    large.point_size_px = 21.0f;
    RenderSettings attenuated = base;
    attenuated.size_mode = PointSizeMode::Attenuated;
    attenuated.world_size = 0.5f;
    RenderSettings adaptive = base;
    adaptive.size_mode = PointSizeMode::Adaptive;
    adaptive.adaptive_scale = 1.5f;
    looks.push_back({"fixed 5 px " + shape_name, small});
    looks.push_back({"fixed 21 px " + shape_name, large});
    looks.push_back({"attenuated " + shape_name, attenuated});
    looks.push_back({"adaptive " + shape_name, adaptive});
  }
  return looks;
}

TEST(PickSplats, EveryCoveredPixelNamesItsFrontMostSplatInEveryLookRasterizerAndEye) {
  headlessContext();
  const PointCloud cloud = wallOnGround();
  std::map<std::tuple<double, double, double>, std::size_t> index_of;
  for (std::size_t k = 0; k < cloud.count; ++k) {
    index_of[{cloud.worldX(k), cloud.worldY(k), cloud.worldZ(k)}] = k;
  }
  const glm::dvec3 eye{0.2, -1.8, 1.0}, look_at{0.0, 1.2, 0.4};
  Camera camera;
  camera.lookAt(eye, look_at, {0, 0, 1});
  camera.fov_y_deg = 60.0;
  constexpr double kSeparation = 0.2, kConvergence = 3.0;
  // Adaptive sizes from a level-of-detail node's spacing (DrawItem::node_spacing), which the CPU
  // reference knows; a whole cloud's per-point spacing is the renderer's own estimate.
  constexpr double kNodeSpacing = 0.3;
  GpuPointCloud gpu(cloud);
  for (const StereoMode mode : {StereoMode::Mono, StereoMode::SideBySide}) {
    const int width = mode == StereoMode::Mono ? 96 : 192, height = 64;
    StereoSettings stereo;
    stereo.mode = mode;
    stereo.eye_separation = kSeparation, stereo.convergence = kConvergence;
    const StereoFrame frame = stereoFrame(camera, stereo, width, height);
    // The same views written out: the whole picture, or its halves for the two eyes.
    std::vector<ReferenceView> views(mode == StereoMode::Mono ? 1 : 2);
    for (std::size_t v = 0; v < views.size(); ++v) {
      views[v].eye = eye, views[v].target = look_at, views[v].fov_y_deg = 60.0;
      views[v].height = height, views[v].width = width / int(views.size());
      views[v].x = int(v) * views[v].width;
      if (mode != StereoMode::Mono) {
        views[v].eye_offset = (v == 0 ? -0.5 : 0.5) * kSeparation;
        views[v].convergence = kConvergence;
      }
    }
    for (const Look& look : everyLook()) {
      DrawSet draw_set = gpu.drawSet();
      if (look.settings.size_mode == PointSizeMode::Adaptive) {
        for (DrawItem& item : draw_set.items) item.node_spacing = float(kNodeSpacing);
      }
      for (const RasterizerKind kind : {RasterizerKind::Points, RasterizerKind::Compute}) {
        const std::string name = look.name + ", " + std::string(rasterizerKindName(kind)) + ", " +
                                 std::string(stereoModeName(mode));
        RenderSettings settings = look.settings;
        settings.rasterizer = kind;
        Renderer renderer;
        RenderTarget target(width, height);
        ASSERT_EQ(renderer.render(draw_set, frame, settings, target.framebuffer(), width, height)
                      .rasterizer,
                  kind)
            << name;
        const double max_point_size = renderer.computeRasterizer().maxPointSize();
        const std::vector<Splat> splats =
            cpuSplats(cloud, views, settings, kNodeSpacing, max_point_size);
        PickSource source(cloud);
        std::size_t checked = 0, empty = 0, large = 0;
        for (const Splat& splat : splats) large += splat.size > ComputeRasterizer::kInlineSplatPx;
        // Per pixel: the splats that surely cover it, and whether one may or may not.
        std::vector<std::vector<const Splat*>> covering_at(std::size_t(width) * height);
        std::vector<char> unsure_at(std::size_t(width) * height, 0);
        for (const Splat& splat : splats) {
          const ReferenceView& vp = views[std::size_t(splat.view)];
          const int x0 = std::max(vp.x, int(std::floor(splat.window.x - splat.size / 2 - 1)));
          const int x1 = std::min(vp.x + vp.width - 1, int(splat.window.x + splat.size / 2 + 1));
          const int y0 = std::max(vp.y, int(std::floor(splat.window.y - splat.size / 2 - 1)));
          const int y1 = std::min(vp.y + vp.height - 1, int(splat.window.y + splat.size / 2 + 1));
          for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
              const Cover cover = covers(splat, x, y, settings.shape);
              const std::size_t pixel = std::size_t(y) * width + x;
              if (cover == Cover::Unsure) unsure_at[pixel] = 1;
              if (cover == Cover::Inside) covering_at[pixel].push_back(&splat);
            }
          }
        }
        for (int y = 0; y < height; ++y) {
          for (int x = 0; x < width; ++x) {
            const int view = renderer.viewAt(x, y);
            const std::size_t pixel = std::size_t(y) * width + x;
            if (unsure_at[pixel]) continue;
            const std::vector<const Splat*>& covering = covering_at[pixel];
            double front = INFINITY;
            for (const Splat* splat : covering) front = std::min(front, splat->depth);
            PickRequest request;
            request.x = x, request.y = y;
            request.radius_px = 0;
            request.last_frame_matches = true;
            const auto picked = pickPoint(renderer, source, draw_set, frame.views,
                                          frame.composition, settings, width, height, request);
            if (covering.empty()) {
              EXPECT_FALSE(picked.has_value()) << name << ": pixel " << x << "," << y;
              ++empty;
              continue;
            }
            ASSERT_TRUE(picked.has_value()) << name << ": nothing at " << x << "," << y;
            EXPECT_EQ(picked->view, view) << name;
            const auto found =
                index_of.find({picked->position.x, picked->position.y, picked->position.z});
            ASSERT_NE(found, index_of.end()) << name << ": not a point of the cloud";
            const auto splat = std::find_if(covering.begin(), covering.end(), [&](const Splat* s) {
              return s->point == found->second;
            });
            ASSERT_NE(splat, covering.end())
                << name << ": point " << found->second << " does not cover " << x << "," << y;
            EXPECT_LE((*splat)->depth, front * (1 + 1e-5))
                << name << ": pixel " << x << "," << y << " names a point behind the front";
            ++checked;
          }
        }
        // A quarter of the picture at least is covered, with background above the horizon.
        EXPECT_GT(checked, std::size_t(width * height / 4)) << name << ": " << checked;
        EXPECT_GT(empty, 0u) << name;
        if (look.name.find("21 px") != std::string::npos) {
          EXPECT_EQ(large, splats.size()) << name;
        }
      }
    }
  }
}

}  // namespace
}  // namespace parallax::test
