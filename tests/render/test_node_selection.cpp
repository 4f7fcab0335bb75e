// Node selection on hand-built hierarchies: the frustum (union of the views), the priority order,
// the point budget, the minimum projected size, residency and proxies.
#include "render/node_selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "fake_octree.h"
#include "render/stereo.h"

namespace parallax {
namespace {

using test::FakeOctree;

Bounds3 cube(double lo, double hi) {
  Bounds3 box;
  box.extend(lo, lo, lo);
  box.extend(hi, hi, hi);
  return box;
}

// A root over [0, 16]^3 with its 8 children; child octant i is node i + 1 and has `counts[i]`
// points.
std::unique_ptr<FakeOctree> rootAndChildren(std::uint32_t root_points,
                                            const std::array<std::uint32_t, 8>& counts) {
  auto octree = std::make_unique<FakeOctree>(cube(0, 16), root_points, 1.0);
  for (int i = 0; i < 8; ++i) octree->addChild(0, i, counts[std::size_t(i)]);
  return octree;
}

SelectionView look(const glm::dvec3& eye, const glm::dvec3& target, double fov_deg,
                   int viewport_height, const Bounds3& scene) {
  View view;
  view.camera.fov_y_deg = fov_deg;
  view.camera.lookAt(eye, target, {0, 1, 0});
  view.viewport = {0, 0, viewport_height, viewport_height};
  return selectionViewFor(view, scene);
}

NodeSelectionSettings unlimited() {
  NodeSelectionSettings settings;
  settings.point_budget = std::numeric_limits<std::uint64_t>::max();
  settings.min_node_size_px = 0.0;
  return settings;
}

using Ids = std::vector<std::int32_t>;

TEST(NodeSelection, NodesBehindTheCameraAreCulled) {
  auto octree = rootAndChildren(100, {1, 1, 1, 1, 1, 1, 1, 1});
  // From the centre of the cube looking along +x: the four children with low x are behind.
  View view;
  view.camera.lookAt({8, 8, 8}, {20, 8, 8}, {0, 0, 1});
  view.viewport = {0, 0, 100, 100};
  const SelectionView selection_view = selectionViewFor(view, octree->info().cube);
  const NodeSelection selection =
      selectNodes(octree->nodes(), std::span(&selection_view, 1), unlimited());
  // The root surrounds the eye (infinite weight); the four children in front are symmetric
  // around the view axis, so they tie and come in index order.
  EXPECT_EQ(selection.nodes, (Ids{0, 5, 6, 7, 8}));
  EXPECT_EQ(selection.culled, (Ids{1, 2, 3, 4}));
  EXPECT_TRUE(std::isinf(selection.weights[0]));
  EXPECT_EQ(selection.point_count, 104u);
  EXPECT_FALSE(selection.budget_reached);
}

TEST(NodeSelection, CullsAgainstTheUnionOfTheEyes) {
  // Two children side by side: [0, 8] and [8, 16] in x (octants 0 and 4).
  FakeOctree octree(cube(0, 16), 10, 1.0);
  const std::int32_t left_child = octree.addChild(0, 0, 5);
  const std::int32_t right_child = octree.addChild(0, 4, 7);
  const Bounds3 scene = octree.info().cube;
  // Narrow eyes (10 degrees) looking straight down, one above each child: at 22 to 30 units
  // each sees less than 2.7 units either side of its own x, so only its own child.
  const SelectionView left = look({4, 4, 30}, {4, 4, 0}, 10.0, 100, scene);
  const SelectionView right = look({12, 4, 30}, {12, 4, 0}, 10.0, 100, scene);

  const NodeSelection left_only = selectNodes(octree.nodes(), std::span(&left, 1), unlimited());
  EXPECT_EQ(left_only.nodes, (Ids{0, left_child}));
  EXPECT_EQ(left_only.culled, (Ids{right_child}));

  const NodeSelection right_only = selectNodes(octree.nodes(), std::span(&right, 1), unlimited());
  EXPECT_EQ(right_only.nodes, (Ids{0, right_child}));

  const std::array<SelectionView, 2> eyes{left, right};
  const NodeSelection both = selectNodes(octree.nodes(), eyes, unlimited());
  // Equal distances and sizes: a tie, broken by index.
  EXPECT_EQ(both.nodes, (Ids{0, left_child, right_child}));
  EXPECT_TRUE(both.culled.empty());
  EXPECT_EQ(both.point_count, 22u);
}

TEST(NodeSelection, NothingWhenTheRootIsOutOfView) {
  auto octree = rootAndChildren(100, {1, 1, 1, 1, 1, 1, 1, 1});
  const SelectionView away = look({8, 8, 40}, {8, 8, 80}, 60.0, 100, octree->info().cube);
  const NodeSelection selection = selectNodes(octree->nodes(), std::span(&away, 1), unlimited());
  EXPECT_TRUE(selection.nodes.empty());
  EXPECT_EQ(selection.point_count, 0u);
}

// Seen from (0, 0, 40) towards the cube's centre, the children's squared distances are
// octant 1: 816, 3 and 5: 944, 7: 1072, 0: 1328, 2 and 4: 1456, 6: 1584.
class PriorityOrder : public ::testing::Test {
 protected:
  std::unique_ptr<FakeOctree> octree = rootAndChildren(100, {10, 20, 30, 40, 50, 60, 70, 80});
  SelectionView view = look({0, 0, 40}, {8, 8, 8}, 60.0, 100, octree->info().cube);
};

TEST_F(PriorityOrder, NodesComeByProjectedSize) {
  const NodeSelection selection = selectNodes(octree->nodes(), std::span(&view, 1), unlimited());
  EXPECT_EQ(selection.nodes, (Ids{0, 2, 4, 6, 8, 1, 3, 5, 7}));
  // Projected radius: half the diagonal of an 8-unit cube, 100 px high, 60 degrees.
  const double radius = 4.0 * std::sqrt(3.0), slope = std::tan(M_PI / 6);
  EXPECT_NEAR(selection.weights[1], radius * 100 / (2 * std::sqrt(816.0) * slope), 1e-9);
  EXPECT_NEAR(selection.weights[8], radius * 100 / (2 * std::sqrt(1584.0) * slope), 1e-9);
  // The root: centre (8, 8, 8), at a distance of sqrt(64 + 64 + 1024).
  EXPECT_NEAR(selection.weights[0], 8.0 * std::sqrt(3.0) * 100 / (2 * std::sqrt(1152.0) * slope),
              1e-9);
  EXPECT_EQ(selection.point_count, 460u);
}

TEST_F(PriorityOrder, StopsExactlyAtTheBudget) {
  NodeSelectionSettings settings = unlimited();
  settings.point_budget = 100 + 20 + 40 + 60;  // root, octants 1, 3, 5 fill it exactly
  NodeSelection selection = selectNodes(octree->nodes(), std::span(&view, 1), settings);
  EXPECT_EQ(selection.nodes, (Ids{0, 2, 4, 6}));
  EXPECT_EQ(selection.point_count, 220u);
  EXPECT_TRUE(selection.budget_reached);

  // One point less: octant 5 (60) no longer fits, and the traversal stops there even though
  // octant 0 (10 points, further away) would fit: everything chosen outranks the rest.
  settings.point_budget = 219;
  selection = selectNodes(octree->nodes(), std::span(&view, 1), settings);
  EXPECT_EQ(selection.nodes, (Ids{0, 2, 4}));
  EXPECT_EQ(selection.point_count, 160u);
}

TEST_F(PriorityOrder, TheRootIsTakenOverBudget) {
  NodeSelectionSettings settings = unlimited();
  settings.point_budget = 50;
  const NodeSelection selection = selectNodes(octree->nodes(), std::span(&view, 1), settings);
  EXPECT_EQ(selection.nodes, (Ids{0}));
  EXPECT_EQ(selection.point_count, 100u);
  EXPECT_TRUE(selection.budget_reached);
}

TEST_F(PriorityOrder, SkipsNodesBelowTheMinimumSize) {
  // Octant 1 projects to 21.0 px, 3 and 5 to 19.5 px, 7 to 18.3 px, 0 to 16.5 px.
  NodeSelectionSettings settings = unlimited();
  settings.min_node_size_px = 19.0;
  const NodeSelection selection = selectNodes(octree->nodes(), std::span(&view, 1), settings);
  EXPECT_EQ(selection.nodes, (Ids{0, 2, 4, 6}));
  EXPECT_FALSE(selection.budget_reached);
  // The root is never skipped for its size.
  settings.min_node_size_px = 1e9;
  EXPECT_EQ(selectNodes(octree->nodes(), std::span(&view, 1), settings).nodes, (Ids{0}));
}

TEST_F(PriorityOrder, ReportsWhatIsNotResident) {
  std::vector<std::uint8_t> resident(9, 0);
  resident[0] = resident[4] = resident[1] = 1;
  const NodeSelection selection =
      selectNodes(octree->nodes(), std::span(&view, 1), unlimited(), resident);
  EXPECT_EQ(selection.missing, (Ids{2, 6, 8, 3, 5, 7}));
}

TEST_F(PriorityOrder, ProxiesAreReportedAndNotEntered) {
  auto proxied = rootAndChildren(100, {10, 20, 30, 40, 50, 60, 70, 80});
  proxied->addChild(8, 0, 5);  // a grandchild under octant 7 (node 8), index 9
  proxied->makeProxy(8);
  const NodeSelection before = selectNodes(proxied->nodes(), std::span(&view, 1), unlimited());
  EXPECT_EQ(before.nodes, (Ids{0, 2, 4, 6, 8, 1, 3, 5, 7}));
  EXPECT_EQ(before.expand, (Ids{8}));
  proxied->expandHierarchy(8);
  const NodeSelection after = selectNodes(proxied->nodes(), std::span(&view, 1), unlimited());
  EXPECT_TRUE(after.expand.empty());
  ASSERT_EQ(after.nodes.size(), 10u);
  EXPECT_EQ(after.point_count, 465u);
}

TEST(NodeSelection, OrthographicSizeIgnoresDistance) {
  auto octree = rootAndChildren(100, {1, 1, 1, 1, 1, 1, 1, 1});
  View view;
  view.camera.projection = Projection::Orthographic;
  view.camera.ortho_height = 40.0;
  view.camera.lookAt({8, 8, 60}, {8, 8, 8}, {0, 1, 0});
  view.viewport = {0, 0, 200, 200};
  const SelectionView selection_view = selectionViewFor(view, octree->info().cube);
  // Every child has the same projected radius, 4 sqrt(3) x 200 / 40, so ties go by index.
  const NodeSelection selection =
      selectNodes(octree->nodes(), std::span(&selection_view, 1), unlimited());
  EXPECT_EQ(selection.nodes, (Ids{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_NEAR(selection.weights[1], 4.0 * std::sqrt(3.0) * 200 / 40, 1e-9);
  EXPECT_NEAR(selection.weights[0], 8.0 * std::sqrt(3.0) * 200 / 40, 1e-9);
}

// The point budget is for the output's pixels: eyes side by side (or one above the other) share
// it, so each eye draws as many points per pixel as mono; eyes on the same pixels do not.
// Seen from (0, 0, 40) the children come in octant order 1, 3, 5, 7, 0, 2, 4, 6 (PriorityOrder);
// with these counts the selections fill 100, 120, 160, 200, 300, 400... points.
class BudgetPerOutputPixel : public ::testing::Test {
 protected:
  std::unique_ptr<FakeOctree> octree = rootAndChildren(100, {100, 20, 100, 40, 100, 40, 100, 100});

  // Views of one camera (so that ties and weights are mono's) at the given canvas rectangles,
  // landing on the given output rectangles.
  std::vector<SelectionView> views(const std::vector<Viewport>& canvas,
                                   const std::vector<Viewport>& output) const {
    std::vector<SelectionView> result;
    for (std::size_t i = 0; i < canvas.size(); ++i) {
      View view;
      view.camera.fov_y_deg = 60.0;
      view.camera.lookAt({0, 0, 40}, {8, 8, 8}, {0, 1, 0});
      view.viewport = canvas[i], view.output = output[i];
      result.push_back(selectionViewFor(view, octree->info().cube));
    }
    return result;
  }
  NodeSelection select(const std::vector<SelectionView>& selection_views) const {
    NodeSelectionSettings settings;
    settings.point_budget = 400, settings.min_node_size_px = 0.0;
    return selectNodes(octree->nodes(), selection_views, settings);
  }
};

TEST_F(BudgetPerOutputPixel, SideBySideEyesDrawMonosPointsPerPixel) {
  // A 200 x 100 window: mono fills the budget, 400 points over 20 000 pixels.
  const NodeSelection mono = select(views({{0, 0, 200, 100}}, {{0, 0, 200, 100}}));
  EXPECT_EQ(mono.nodes, (Ids{0, 2, 4, 6, 8, 1}));
  EXPECT_EQ(mono.point_count, 400u);
  // Two 100 x 100 eyes: 200 points, drawn in each eye's 10 000 pixels.
  const std::vector<Viewport> halves = {{0, 0, 100, 100}, {100, 0, 100, 100}};
  const NodeSelection sbs = select(views(halves, halves));
  EXPECT_EQ(sbs.nodes, (Ids{0, 2, 4, 6}));
  EXPECT_EQ(sbs.point_count, 200u);
  EXPECT_TRUE(sbs.budget_reached);
  EXPECT_EQ(double(sbs.point_count) / (100 * 100), double(mono.point_count) / (200 * 100));
  // One above the other: the same.
  const std::vector<Viewport> rows = {{0, 50, 200, 50}, {0, 0, 200, 50}};
  EXPECT_EQ(select(views(rows, rows)).nodes, (Ids{0, 2, 4, 6}));
}

TEST_F(BudgetPerOutputPixel, EyesOnTheSamePixelsKeepTheWholeBudget) {
  // Anaglyph: full-size eyes side by side in a double-width canvas, each over the whole output.
  const NodeSelection anaglyph =
      select(views({{0, 0, 200, 100}, {200, 0, 200, 100}}, {{0, 0, 200, 100}, {0, 0, 200, 100}}));
  EXPECT_EQ(anaglyph.nodes, (Ids{0, 2, 4, 6, 8, 1}));
  // Views that do not state their output (a headset's eyes) keep it too.
  const NodeSelection headset =
      select(views({{0, 0, 100, 100}, {100, 0, 100, 100}}, {{0, 0, 0, 0}, {0, 0, 0, 0}}));
  EXPECT_EQ(headset.nodes, (Ids{0, 2, 4, 6, 8, 1}));
}

TEST(NodeSelection, StereoFramesShareTheBudgetByTheirEyesPixels) {
  Camera camera;
  camera.lookAt({0, 0, 40}, {8, 8, 8}, {0, 1, 0});
  auto budget = [&](StereoMode mode, int width, int height) {
    std::vector<SelectionView> views;
    for (const View& view : stereoFrame(camera, {.mode = mode}, width, height).views)
      views.push_back(selectionViewFor(view, cube(0, 16)));
    return viewsPointBudget(3'000'000, views);
  };
  EXPECT_EQ(budget(StereoMode::Mono, 1920, 1080), 3'000'000u);
  EXPECT_EQ(budget(StereoMode::SideBySide, 1920, 1080), 1'500'000u);
  EXPECT_EQ(budget(StereoMode::SideBySideSqueezed, 1920, 1080), 1'500'000u);
  EXPECT_EQ(budget(StereoMode::TopBottom, 1920, 1080), 1'500'000u);
  EXPECT_EQ(budget(StereoMode::Anaglyph, 1920, 1080), 3'000'000u);
  EXPECT_EQ(budget(StereoMode::Interlaced, 1920, 1080), 3'000'000u);
  EXPECT_EQ(budget(StereoMode::QuadBuffer, 1920, 1080), 3'000'000u);
  // An odd width: halves of 960 and 961 columns; the larger sets the share, rounded down.
  EXPECT_EQ(budget(StereoMode::SideBySide, 1921, 1080), 3'000'000u * 961 / 1921);
  // No overflow for an unlimited budget.
  std::vector<SelectionView> halves(2);
  halves[0].pixels = {0, 0, 100, 100}, halves[1].pixels = {100, 0, 100, 100};
  EXPECT_EQ(viewsPointBudget(std::numeric_limits<std::uint64_t>::max(), halves),
            std::numeric_limits<std::uint64_t>::max() / 2);
}

}  // namespace
}  // namespace parallax
