// The overlay pass on llvmpipe: a line's pixels where a projection in double of its endpoints,
// written out in the test from the camera's eye, target and field of view, puts them (at UTM
// coordinates), drawn over points behind it and faded behind points
// in front of it, in each eye of a side-by-side stereo frame at that eye's projection; labels
// in the atlas's font.
#include <gtest/gtest.h>

#include <cmath>

#include "render/overlay_geometry.h"
#include "render/renderer.h"
#include "render/stereo.h"
#include "render_test_support.h"

namespace parallax::test {
namespace {

constexpr double kEast = 500000.0, kNorth = 5000000.0, kUp = 100.0;
constexpr int kWidth = 256, kHeight = 192;

glm::dvec3 utm(double x, double y, double z) {
  return {kEast + x, kNorth + y, kUp + z};
}

// Two big points: one in front of the line's middle (z +5, towards the camera), one behind the
// line at x +1.5 (z -5). Blue and green (makeCloud's colours are replaced).
PointCloud occluders() {
  PointCloud cloud = makeCloud({{kEast, kNorth, kUp + 5}, {kEast + 1.5, kNorth, kUp - 5}},
                               {kEast, kNorth, kUp}, 1.0 / 1024);
  cloud.colors[0] = {0, 0, 255, 255};
  cloud.colors[1] = {0, 255, 0, 255};
  return cloud;
}

RenderSettings bigSquares(RasterizerKind rasterizer = RasterizerKind::Points) {
  RenderSettings settings;
  settings.point_size_px = 15;
  settings.rasterizer = rasterizer;
  return settings;
}

OverlayScene yellowLine() {
  OverlayScene scene;
  OverlayPolyline line;
  line.points = {utm(-3, 0, 0), utm(3, 0, 0)};
  line.color = {1, 1, 0, 1};
  line.width_px = 3;
  scene.polylines.push_back(line);
  return scene;
}

// The camera of every test, written out: the eye 20 above the origin, looking down at it, +y up
// in the picture, 40 degrees of vertical field of view.
constexpr double kEyeHeight = 20.0, kFovYDeg = 40.0;

Camera frontCamera() {
  Camera camera;
  camera.lookAt(utm(0, 0, kEyeHeight), utm(0, 0, 0), {0, 1, 0});
  camera.fov_y_deg = kFovYDeg;
  return camera;
}

// The pixel (top-row-first image coordinates) where `world` lands in `view`, projected here from
// the camera's definition alone (independently of the product's camera matrices and the overlay's
// projection): looking down -z from kEyeHeight, picture right is +x and up is +y; a point at depth
// d and lateral offset x is at x / (d tan(fov / 2) aspect) in normalized coordinates. In stereo,
// `eye_offset` (metres along +x, -half the separation for the left eye) moves the eye and
// `convergence` skews its frustum so that the plane at that depth has no parallax
// (src/render/stereo.h): x' = (x - offset) / d + offset / convergence.
std::pair<int, int> cpuPixel(const View& view, const glm::dvec3& world, double eye_offset = 0.0,
                             double convergence = 1.0) {
  const double x = world.x - kEast, y = world.y - kNorth, depth = kEyeHeight - (world.z - kUp);
  const double tan_half = std::tan(kFovYDeg * 0.5 * std::acos(-1.0) / 180.0);
  const double aspect = double(view.viewport.width) / view.viewport.height;
  const double nx = ((x - eye_offset) / depth + eye_offset / convergence) / (tan_half * aspect);
  const double ny = (y / depth) / tan_half;
  const double px = view.viewport.x + (nx * 0.5 + 0.5) * view.viewport.width;
  const double py = view.viewport.y + (ny * 0.5 + 0.5) * view.viewport.height;
  return {int(std::floor(px)), kHeight - 1 - int(std::floor(py))};
}

std::array<int, 3> rgbAt(const std::vector<std::uint8_t>& rgba, std::pair<int, int> pixel) {
  const std::size_t at = (std::size_t(pixel.second) * kWidth + std::size_t(pixel.first)) * 4;
  return {rgba[at], rgba[at + 1], rgba[at + 2]};
}

void expectColor(const std::array<int, 3>& got, const std::array<int, 3>& want, int tolerance,
                 const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(got[c], want[c], tolerance)
        << what << ": (" << got[0] << ", " << got[1] << ", " << got[2] << ")";
  }
}

// Under both rasterizers: the overlay's occlusion reads the depth each of them leaves (15-pixel
// squares are the compute rasterizer's large splats).
class OverlayOcclusion : public ::testing::TestWithParam<RasterizerKind> {};

TEST_P(OverlayOcclusion, LineLandsOnTheProjectedPixelsAndFadesBehindNearerPoints) {
  headlessContext();
  const GpuPointCloud cloud(occluders());
  Renderer renderer;
  renderer.setOverlay(yellowLine());
  RenderTarget target(kWidth, kHeight);
  const View view{frontCamera(), {0, 0, kWidth, kHeight}};
  expectDrawnBy(renderer.render(cloud, std::span(&view, 1), bigSquares(GetParam()),
                                target.framebuffer(), kWidth, kHeight),
                GetParam());
  const auto rgba = target.readRgba();

  // Open line over the background: pure yellow, along the whole projected segment.
  for (double x : {-2.5, -1.0, 0.8, 2.5}) {
    expectColor(rgbAt(rgba, cpuPixel(view, utm(x, 0, 0))), {255, 255, 0}, 0,
                "line at x " + std::to_string(x));
  }
  // Off the line (3 pixels wide): background.
  const auto [lx, ly] = cpuPixel(view, utm(-2, 0, 0));
  expectColor(rgbAt(rgba, {lx, ly - 4}), {0, 0, 0}, 0, "above the line");
  expectColor(rgbAt(rgba, {lx, ly + 4}), {0, 0, 0}, 0, "below the line");
  // The green point behind the line: the line is drawn over it, whole.
  expectColor(rgbAt(rgba, cpuPixel(view, utm(1.5, 0, 0))), {255, 255, 0}, 0, "over the far point");
  expectColor(rgbAt(rgba, cpuPixel(view, utm(1.5, 0.2, 0))), {0, 255, 0}, 0, "the far point");
  // The blue point in front of the line's middle hides it: the line is faded to 30 % there.
  expectColor(rgbAt(rgba, cpuPixel(view, utm(0, 0, 0))),
              {int(0.3 * 255), int(0.3 * 255), int(0.7 * 255)}, 2, "behind the near point");
}

INSTANTIATE_TEST_SUITE_P(BothRasterizers, OverlayOcclusion,
                         ::testing::Values(RasterizerKind::Points, RasterizerKind::Compute),
                         [](const ::testing::TestParamInfo<RasterizerKind>& param_info) {
                           return std::string(rasterizerKindName(param_info.param));
                         });

TEST(OverlayPass, EachStereoEyeDrawsTheLineAtItsOwnProjection) {
  headlessContext();
  const GpuPointCloud cloud(occluders());
  Renderer renderer;
  // A vertical line at x -2: its two pictures differ by the eyes' parallax.
  OverlayScene scene;
  scene.polylines.push_back({{utm(-2, -2, 0), utm(-2, 2, 0)}, false, {1, 0, 1, 1}, 3});
  renderer.setOverlay(scene);
  RenderTarget target(kWidth, kHeight);
  StereoSettings stereo;
  stereo.mode = StereoMode::SideBySide;
  stereo.eye_separation = 1.0;
  stereo.convergence = 10.0;
  const StereoFrame frame = stereoFrame(frontCamera(), stereo, kWidth, kHeight);
  ASSERT_EQ(frame.views.size(), 2u);
  renderer.render(cloud, frame.views, bigSquares(), target.framebuffer(), kWidth, kHeight,
                  frame.composition);
  const auto rgba = target.readRgba();
  int columns[2];
  for (int eye = 0; eye < 2; ++eye) {
    const double offset = (eye == 0 ? -0.5 : 0.5) * stereo.eye_separation;
    const auto pixel =
        cpuPixel(frame.views[std::size_t(eye)], utm(-2, 1, 0), offset, stereo.convergence);
    columns[eye] = pixel.first - frame.views[std::size_t(eye)].viewport.x;
    expectColor(rgbAt(rgba, pixel), {255, 0, 255}, 0, "eye " + std::to_string(eye));
    expectColor(rgbAt(rgba, {pixel.first + 4, pixel.second}), {0, 0, 0}, 0,
                "right of the line, eye " + std::to_string(eye));
  }
  // Behind the convergence plane (20 units away, converged at 10): uncrossed parallax, the
  // right eye's picture of it further right in its half.
  EXPECT_GT(columns[1], columns[0]);
}

TEST(OverlayPass, LabelTextIsDrawnInTheFontAtItsAnchor) {
  headlessContext();
  const GpuPointCloud cloud(occluders());
  Renderer renderer;
  OverlayScene scene;
  scene.labels.push_back({utm(-2.5, -1.5, 0), "12.34 m", {1, 1, 1, 1}});
  renderer.setOverlay(scene);
  RenderTarget target(kWidth, kHeight);
  const View view{frontCamera(), {0, 0, kWidth, kHeight}};
  renderer.render(cloud, std::span(&view, 1), bigSquares(), target.framebuffer(), kWidth, kHeight);
  const auto rgba = target.readRgba();
  // The text's box starts 8 pixels right of and above the anchor; its glyphs are white pixels
  // on the dark box, none left of the anchor.
  const auto [ax, ay] = cpuPixel(view, utm(-2.5, -1.5, 0));
  int white = 0, white_left = 0;
  for (int y = ay - 30; y <= ay; ++y) {
    for (int x = ax - 20; x < ax + 70; ++x) {
      if (x < 0 || y < 0) continue;
      const auto c = rgbAt(rgba, {x, y});
      if (c[0] > 200 && c[1] > 200 && c[2] > 200) (x < ax ? white_left : white) += 1;
    }
  }
  // "12.34 m" in a 13-pixel font: dozens of lit pixels.
  EXPECT_GT(white, 40);
  EXPECT_EQ(white_left, 0);
  // Drawing the label needs the renderer's font: its atlas is not empty.
  EXPECT_GT(OverlayFont().atlasWidth(), 0);
}

TEST(OverlayGeometry, SegmentThroughTheNearPlaneIsClippedNotMirrored) {
  const View view{frontCamera(), {0, 0, kWidth, kHeight}};
  const ClipRange range{1, 100};
  // From in front of the camera to far behind it: only the front part is drawn.
  OverlayScene scene;
  scene.polylines.push_back({{utm(0, 0, 0), utm(0, 4, 40)}, false, {1, 1, 1, 1}, 2});
  const auto triangles = overlayTriangles(scene, view, range, nullptr);
  ASSERT_EQ(triangles.size(), 6u);
  for (const OverlayVertex& v : triangles) {
    // Every vertex is in front: a positive inverse depth no larger than 1 / near.
    EXPECT_GT(v.inverse_depth, 0.0f);
    EXPECT_LE(v.inverse_depth, 1.0f + 1e-6f);
    // The segment goes up the screen from the centre (y of the world is up in the picture).
    EXPECT_GE(v.y, kHeight / 2.0f - 2.0f);
  }
  // Entirely behind: nothing.
  OverlayScene behind;
  behind.polylines.push_back({{utm(0, 0, 30), utm(1, 0, 40)}, false, {1, 1, 1, 1}, 2});
  EXPECT_TRUE(overlayTriangles(behind, view, range, nullptr).empty());
  EXPECT_FALSE(projectToView(view, range, utm(0, 0, 30)));
  const auto centre = projectToView(view, range, utm(0, 0, 0));
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->x, kWidth / 2.0, 1e-9);
  EXPECT_NEAR(centre->y, kHeight / 2.0, 1e-9);
  EXPECT_NEAR(centre->eye_depth, 20.0, 1e-9);
}

// A picture's quad (OverlayImage) rising from the ground in front of the camera to far behind it:
// cut where it crosses the near plane, the cut's corners carrying the picture's coordinates there
// (over their eye depth, for the pass's perspective-correct interpolation).
TEST(OverlayGeometry, ImageQuadThroughTheNearPlaneIsClippedWithItsPictureCoordinates) {
  const View view{frontCamera(), {0, 0, kWidth, kHeight}};
  const ClipRange range{1, 100};
  OverlayImage image;
  image.width = image.height = 2;
  // Bottom at depth 20, top at depth -20: the near plane (depth 1) cuts both sides 19/40 of the
  // way up, where the picture's v (0 at its top) is 1 - 19/40.
  image.corners = {utm(0, 0, 0), utm(2, 0, 0), utm(2, 4, 40), utm(0, 4, 40)};
  const auto triangles = overlayImageTriangles(image, view, range);
  ASSERT_EQ(triangles.size(), 6u);  // the kept quad: two triangles
  int bottom = 0, cut = 0;
  for (const OverlayVertex& v : triangles) {
    const double depth = 1.0 / v.inverse_depth, u = v.u * depth, t = v.v * depth;
    EXPECT_EQ(v.test_x, -1.0f);  // tested per fragment
    if (std::abs(depth - 20.0) < 1e-3) {
      ++bottom;
      EXPECT_NEAR(t, 1.0, 1e-5);
      EXPECT_TRUE(std::abs(u) < 1e-5 || std::abs(u - 1.0) < 1e-5) << u;
    } else {
      ++cut;
      EXPECT_NEAR(depth, 1.0, 1e-5);
      EXPECT_NEAR(t, 1.0 - 19.0 / 40.0, 1e-5);
      EXPECT_TRUE(std::abs(u) < 1e-5 || std::abs(u - 1.0) < 1e-5) << u;
    }
  }
  EXPECT_GT(bottom, 0);
  EXPECT_GT(cut, 0);
  // Wholly behind the camera: nothing.
  image.corners = {utm(0, 0, 30), utm(2, 0, 30), utm(2, 4, 40), utm(0, 4, 40)};
  EXPECT_TRUE(overlayImageTriangles(image, view, range).empty());
}

// A font of identical boxes: every glyph 6 x 10 pixels, 7 apart, lines 12 high.
class BoxGlyphs : public OverlayGlyphs {
 public:
  BoxGlyphs() { glyph_ = {0, 0, 6, 10, 0, 0, 1, 1, 7}; }
  const OverlayGlyph& glyph(unsigned) const override { return glyph_; }
  float lineHeight() const override { return 12.0f; }

 private:
  OverlayGlyph glyph_;
};

// Labels never overlap: the last placed at its anchor (a measurement's total), those that would
// cover it moved a line away; none dropped while a free line is near.
TEST(OverlayGeometry, LabelsAtTheSamePlaceAreMovedApart) {
  const View view{frontCamera(), {0, 0, kWidth, kHeight}};
  const ClipRange range{1, 100};
  OverlayScene scene;
  scene.labels.push_back({utm(0, 0, 0), "12.345 m", {1, 1, 1, 1}});
  scene.labels.push_back({utm(0, 0, 0), "6.789 m", {1, 1, 1, 1}});
  scene.labels.push_back({utm(0, 0, 0), "area 42 m2", {1, 1, 1, 1}});
  const BoxGlyphs glyphs;
  const auto triangles = overlayTriangles(scene, view, range, &glyphs);
  // The dark boxes behind the texts: six solid black vertices each.
  struct Box {
    float x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  for (std::size_t i = 0; i + 6 <= triangles.size(); i += 6) {
    const OverlayVertex& v = triangles[i];
    if (v.u >= 0 || v.color[0] != 0 || v.color[1] != 0 || v.color[2] != 0) continue;
    Box box{INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (std::size_t k = i; k < i + 6; ++k) {
      box.x0 = std::min(box.x0, triangles[k].x), box.x1 = std::max(box.x1, triangles[k].x);
      box.y0 = std::min(box.y0, triangles[k].y), box.y1 = std::max(box.y1, triangles[k].y);
    }
    boxes.push_back(box);
  }
  ASSERT_EQ(boxes.size(), 3u);
  // The first box is the last label's, at its anchor: 8 pixels up-right, 3 of padding.
  EXPECT_FLOAT_EQ(boxes[0].x0, kWidth / 2.0f + 8 - 3);
  EXPECT_FLOAT_EQ(boxes[0].y0, kHeight / 2.0f + 8 - 3);
  EXPECT_FLOAT_EQ(boxes[0].x1 - boxes[0].x0, 10 * 7 + 6);
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      const bool overlap = boxes[a].x0 < boxes[b].x1 && boxes[b].x0 < boxes[a].x1 &&
                           boxes[a].y0 < boxes[b].y1 && boxes[b].y0 < boxes[a].y1;
      EXPECT_FALSE(overlap) << "labels " << a << " and " << b << " overlap";
    }
  }
}

}  // namespace
}  // namespace parallax::test
