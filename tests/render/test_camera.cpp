// Camera unit tests: no GL needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <vector>

#include "core/error.h"
#include "render/camera.h"
#include "render/camera_path.h"
#include "render/frustum.h"
#include "render/view_extent.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

TEST(Camera, LookAtLooksAtTheTarget) {
  Camera camera;
  camera.lookAt({10, 0, 0}, {0, 0, 0}, {0, 0, 1});
  expectNear(camera.forward(), {-1, 0, 0}, 1e-12);
  expectNear(camera.up(), {0, 0, 1}, 1e-12);
  expectNear(camera.right(), {0, 1, 0}, 1e-12);
  const glm::dvec4 eye = camera.viewMatrix() * glm::dvec4(0, 0, 0, 1);
  expectNear(glm::dvec3(eye), {0, 0, -10}, 1e-12);
}

TEST(Camera, TurntableOrbitReachesThePoleWithoutGimbalLock) {
  Camera camera;
  camera.lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
  // Pitch far past the pole: the elevation stops at the pole (looking straight down).
  camera.orbit(0.0, -3.0, OrbitMode::Turntable);
  expectNear(camera.forward(), {0, 0, -1}, 1e-9);
  expectNear(camera.position, {0, 0, 10}, 1e-9);
  // At the pole, yaw still turns the view about the vertical: nothing is locked.
  const glm::dvec3 right_before = camera.right();
  camera.orbit(std::numbers::pi / 2, 0.0, OrbitMode::Turntable);
  expectNear(camera.forward(), {0, 0, -1}, 1e-9);
  EXPECT_NEAR(glm::dot(right_before, camera.right()), 0.0, 1e-9);
  // And pitching back leaves the pole on the side the yaw chose.
  camera.orbit(0.0, std::numbers::pi / 4, OrbitMode::Turntable);
  EXPECT_TRUE(finite(camera.position));
  EXPECT_NEAR(glm::length(camera.position), 10.0, 1e-9);
  EXPECT_NEAR(glm::dot(camera.forward(), glm::dvec3(0, 0, 1)), -std::sin(std::numbers::pi / 4),
              1e-9);
  EXPECT_NEAR(glm::length(camera.orientation), 1.0, 1e-12);
}

TEST(Camera, LookAtStraightDownStillOrbits) {
  Camera camera;
  camera.lookAt({0, 0, 10}, {0, 0, 0}, {0, 0, 1});  // view parallel to up
  EXPECT_TRUE(finite(camera.right()));
  camera.orbit(0.3, 0.2, OrbitMode::Turntable);
  EXPECT_TRUE(finite(camera.position));
  EXPECT_NEAR(glm::length(camera.position), 10.0, 1e-9);
  EXPECT_LT(glm::dot(camera.forward(), glm::dvec3(0, 0, 1)), -0.9);
}

TEST(Camera, FreeOrbitPassesOverThePole) {
  Camera camera;
  camera.lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
  for (int i = 0; i < 8; ++i)
    camera.orbit(0.0, -std::numbers::pi / 8, OrbitMode::Free);  // half a turn
  expectNear(camera.position, {0, 10, 0}, 1e-9);
  expectNear(camera.forward(), {0, -1, 0}, 1e-9);
  expectNear(camera.up(), {0, 0, -1}, 1e-9);  // upside down: free rotation has no limits
}

TEST(Camera, PanMovesCameraAndPivotTogether) {
  Camera camera;
  camera.lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
  camera.pan(100, 0, 1000);
  EXPECT_NEAR(camera.pivot.y, 0.0, 1e-12);
  EXPECT_LT(camera.pivot.x, 0.0);  // the scene follows the mouse to the right
  expectNear(camera.position - camera.pivot, {0, -10, 0}, 1e-12);
}

TEST(Camera, DollyKeepsThePointUnderTheCursor) {
  Camera camera;
  camera.lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
  const double aspect = 1.5;
  const glm::dvec2 cursor(0.4, -0.3);
  auto underCursor = [&] {
    const double tan_half = std::tan(glm::radians(camera.fov_y_deg) / 2);
    const glm::dvec3 ray = camera.forward() + camera.right() * (cursor.x * tan_half * aspect) +
                           camera.up() * (cursor.y * tan_half);
    // Where the ray meets the plane y = 0 (the pivot's depth plane).
    const double t = -camera.position.y / ray.y;
    return camera.position + ray * t;
  };
  const glm::dvec3 before = underCursor();
  camera.dolly(0.5, cursor, aspect);
  expectNear(underCursor(), before, 1e-9);
  EXPECT_NEAR(camera.position.y, -5.0, 1e-9);
}

TEST(Camera, FitToBoundsContainsEveryPoint) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    Bounds3 bounds;
    const glm::dvec3 center(500000 + 1000 * unit(random), 5e6 * (1 + unit(random) * 0.01), 0.0);
    const glm::dvec3 half(1 + 100 * std::abs(unit(random)), 1 + 100 * std::abs(unit(random)),
                          0.1 + 10 * std::abs(unit(random)));
    bounds.extend(center.x - half.x, center.y - half.y, center.z - half.z);
    bounds.extend(center.x + half.x, center.y + half.y, center.z + half.z);
    Camera camera;
    camera.lookAt({0, 0, 0}, {unit(random), unit(random), unit(random)}, {0, 0, 1});
    camera.projection = trial % 2 ? Projection::Orthographic : Projection::Perspective;
    const double aspect = 0.5 + 2.0 * std::abs(unit(random));
    camera.fitToBounds(bounds, aspect);
    const glm::dmat4 projection = camera.projectionMatrix(aspect, camera.clipRange(bounds));
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p(corner & 1 ? bounds.max[0] : bounds.min[0],
                         corner & 2 ? bounds.max[1] : bounds.min[1],
                         corner & 4 ? bounds.max[2] : bounds.min[2]);
      const glm::dvec3 eye = glm::dmat3(camera.viewMatrix()) * (p - camera.position);
      const glm::dvec4 clip = projection * glm::dvec4(eye, 1.0);
      ASSERT_GT(clip.w, 0.0);
      EXPECT_LE(std::abs(clip.x / clip.w), 1.0) << "trial " << trial;
      EXPECT_LE(std::abs(clip.y / clip.w), 1.0) << "trial " << trial;
      EXPECT_GE(clip.z / clip.w, 0.0) << "trial " << trial;
      EXPECT_LE(clip.z / clip.w, 1.0) << "trial " << trial;
    }
  }
}

// Normalised device coordinates (x, y) of `points` seen by `camera`, and whether all are ahead.
struct Projected {
  double min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY, max_y = -INFINITY;
  bool all_ahead = true;
};

Projected project(const Camera& camera, const std::vector<glm::dvec3>& points, double aspect) {
  Bounds3 bounds;
  for (const glm::dvec3& p : points) bounds.extend(p.x, p.y, p.z);
  const glm::dmat4 projection = camera.projectionMatrix(aspect, camera.clipRange(bounds));
  Projected result;
  for (const glm::dvec3& p : points) {
    const glm::dvec3 eye = glm::dmat3(camera.viewMatrix()) * (p - camera.position);
    const glm::dvec4 clip = projection * glm::dvec4(eye, 1.0);
    if (!(clip.w > 0.0) || clip.z / clip.w < 0.0 || clip.z / clip.w > 1.0) result.all_ahead = false;
    result.min_x = std::min(result.min_x, clip.x / clip.w);
    result.max_x = std::max(result.max_x, clip.x / clip.w);
    result.min_y = std::min(result.min_y, clip.y / clip.w);
    result.max_y = std::max(result.max_y, clip.y / clip.w);
  }
  return result;
}

// A scan-like cloud: a bumpy ground disc and a few towers on it, off the origin at UTM-like
// coordinates, so that its box has empty corners and its middle is not the box's.
std::vector<glm::dvec3> scanLikePoints(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const glm::dvec3 origin(512000 + 1000 * unit(random), 5.4e6 + 1000 * unit(random), 300.0);
  const double radius = 20 + 200 * unit(random);
  std::vector<glm::dvec3> points;
  for (int i = 0; i < 3000; ++i) {
    const double r = radius * std::sqrt(unit(random)), a = 2 * std::numbers::pi * unit(random);
    points.push_back(
        origin + glm::dvec3(r * std::cos(a), 0.6 * r * std::sin(a), 0.02 * radius * std::sin(r)));
  }
  for (int tower = 0; tower < 3; ++tower) {
    const glm::dvec3 base = origin + glm::dvec3(radius * (unit(random) - 0.5),
                                                0.6 * radius * (unit(random) - 0.5), 0.0);
    for (int i = 0; i < 200; ++i) {
      points.push_back(base + glm::dvec3(unit(random), unit(random), 0.3 * radius * unit(random)));
    }
  }
  return points;
}

// A camera at the origin looking down at a random direction, orthographic on odd trials, with a
// field of view of 30-70 degrees.
Camera randomDownwardCamera(std::mt19937_64& random, int trial) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Camera camera;
  camera.lookAt({0, 0, 0}, {unit(random), unit(random), -std::abs(unit(random)) - 0.2}, {0, 0, 1});
  camera.projection = trial % 2 ? Projection::Orthographic : Projection::Perspective;
  camera.fov_y_deg = 30 + 40 * std::abs(unit(random));
  return camera;
}

TEST(Camera, FitToPointsFillsTheViewOnOneAxisCentredWithTheMargin) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double keep = 1.0 - Camera::kFitMargin;
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<glm::dvec3> points = scanLikePoints(random);
    Camera camera = randomDownwardCamera(random, trial);
    const double aspect = 0.5 + 2.0 * std::abs(unit(random));
    const glm::dquat orientation = camera.orientation;
    camera.fitToPoints(points, aspect);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(camera.orientation, orientation);
    const Projected p = project(camera, points, aspect);
    EXPECT_TRUE(p.all_ahead);
    // Inside the margin on both axes, reaching it on one, centred on both.
    const double tolerance = 1e-6;
    EXPECT_LE(std::max({-p.min_x, p.max_x, -p.min_y, p.max_y}), keep + tolerance);
    EXPECT_GE(std::max(p.max_x - p.min_x, p.max_y - p.min_y), 2 * keep - tolerance);
    EXPECT_NEAR(p.min_x + p.max_x, 0.0, 1e-6);
    EXPECT_NEAR(p.min_y + p.max_y, 0.0, 1e-6);
    // The pivot is on the view axis, in front of the camera.
    const glm::dvec3 to_pivot = camera.pivot - camera.position;
    EXPECT_GT(glm::dot(to_pivot, camera.forward()), 0.0);
    EXPECT_LT(glm::length(glm::cross(glm::normalize(to_pivot), camera.forward())), 1e-9);
  }
}

// Fitted into a part of the view (the viewer's panel covers the rest): centred in that part and
// filling it as a view of its width would be filled, the pivot on the ray through its middle.
TEST(Camera, FitToPointsIntoAPartOfTheViewCentresThemThere) {
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double keep = 1.0 - Camera::kFitMargin;
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<glm::dvec3> points = scanLikePoints(random);
    Camera camera = randomDownwardCamera(random, trial);
    const double aspect = 0.5 + 2.0 * std::abs(unit(random));
    const double x_from = -0.6 + 0.5 * std::abs(unit(random)), x_to = 1.0;  // 40-65 % covered
    const double half = 0.5 * (x_to - x_from), centre = 0.5 * (x_from + x_to);
    const glm::dquat orientation = camera.orientation;
    camera.fitToPoints(points, aspect, Camera::kFitMargin, x_from, x_to);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(camera.orientation, orientation);
    const Projected p = project(camera, points, aspect);
    EXPECT_TRUE(p.all_ahead);
    const double tolerance = 1e-6;
    // Inside the part less its margin, reaching it on one axis, centred in the part on x.
    EXPECT_GE(p.min_x, centre - half * keep - tolerance);
    EXPECT_LE(p.max_x, centre + half * keep + tolerance);
    EXPECT_LE(std::max(-p.min_y, p.max_y), keep + tolerance);
    EXPECT_TRUE(p.max_x - p.min_x >= 2 * half * keep - tolerance ||
                p.max_y - p.min_y >= 2 * keep - tolerance);
    EXPECT_NEAR(p.min_x + p.max_x, 2 * centre, 1e-6);
    EXPECT_NEAR(p.min_y + p.max_y, 0.0, 1e-6);
    // The pivot projects to the part's middle.
    const Projected pivot = project(camera, std::vector<glm::dvec3>{camera.pivot}, aspect);
    EXPECT_NEAR(pivot.max_x, centre, 1e-7);
    EXPECT_NEAR(pivot.max_y, 0.0, 1e-7);
  }
}

TEST(Camera, FitToPointsIsTighterThanTheBoxForAScan) {
  std::mt19937_64 random(5);
  const std::vector<glm::dvec3> points = scanLikePoints(random);
  Bounds3 bounds;
  for (const glm::dvec3& p : points) bounds.extend(p.x, p.y, p.z);
  Camera box = defaultCameraFor(bounds, 16.0 / 9.0), fitted = box;
  fitted.fitToPoints(points, 16.0 / 9.0);
  const Projected by_box = project(box, points, 16.0 / 9.0);
  const Projected by_points = project(fitted, points, 16.0 / 9.0);
  // The box's fit leaves a good part of the picture empty (the scan's extent is what counts).
  EXPECT_LT(by_box.max_x - by_box.min_x, 0.9 * (by_points.max_x - by_points.min_x));
}

TEST(Camera, FitToPointsOfOnePointAndOfNone) {
  Camera camera;
  camera.lookAt({0, -10, 5}, {0, 0, 0}, {0, 0, 1});
  const Camera before = camera;
  camera.fitToPoints({}, 1.5);
  EXPECT_EQ(camera, before);
  const std::vector<glm::dvec3> one{{512345.0, 5412345.0, 100.0}};
  camera.fitToPoints(one, 1.5);
  EXPECT_TRUE(finite(camera.position));
  const Projected p = project(camera, one, 1.5);
  EXPECT_TRUE(p.all_ahead);
  EXPECT_NEAR(p.max_x, 0.0, 1e-6);
  EXPECT_NEAR(p.max_y, 0.0, 1e-6);
}

TEST(ViewExtent, SmallCloudsGiveEveryPointLargeOnesAStrideAndTheExtremes) {
  PointCloud cloud;
  cloud.quantization.scale = {0.01, 0.01, 0.01};
  cloud.quantization.offset = {500000.0, 5000000.0, 0.0};
  const std::size_t count = 10000;
  cloud.count = count;
  cloud.positions = Column<Int3>(count);
  for (std::size_t i = 0; i < count; ++i) {
    cloud.positions[i] = {std::int32_t(i % 100), std::int32_t(i / 100), std::int32_t(i % 7)};
  }
  cloud.positions[4321] = {-500, 20, 3};  // the lowest x, off the stride
  cloud.positions[7777] = {20, 20, 900};  // the highest z
  cloud.computeBounds();
  const ViewExtent all = viewExtentOf(cloud);
  ASSERT_EQ(all.points.size(), count);
  EXPECT_EQ(all.points[4321],
            glm::dvec3(cloud.worldX(4321), cloud.worldY(4321), cloud.worldZ(4321)));
  const ViewExtent some = viewExtentOf(cloud, 100);
  ASSERT_EQ(some.points.size(), 100u);
  auto has = [&](std::size_t i) {
    const glm::dvec3 p(cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i));
    return std::find(some.points.begin(), some.points.end(), p) != some.points.end();
  };
  EXPECT_TRUE(has(4321));
  EXPECT_TRUE(has(7777));
  EXPECT_TRUE(has(0));
  EXPECT_EQ(some.bounds.min, cloud.bounds.min);
  EXPECT_EQ(some.bounds.max, cloud.bounds.max);
}

TEST(Camera, ClipRangeKeepsPointsNearTheEye) {
  Bounds3 bounds;
  bounds.extend(-100, -100, -100);
  bounds.extend(100, 100, 100);
  Camera camera;
  camera.lookAt({0, 0, 0}, {0, 1, 0}, {0, 0, 1});  // inside the box
  const ClipRange range = camera.clipRange(bounds);
  EXPECT_LE(range.near_plane, 1e-3);
  EXPECT_GE(range.far_plane, 100.0);  // the farthest corner's depth along the view
}

TEST(Camera, JsonRoundTrip) {
  TempDir dir;
  Camera camera;
  camera.lookAt({512345.125, 5412345.5, 312.25}, {512340.0, 5412350.0, 300.0}, {0, 0, 1});
  camera.projection = Projection::Orthographic;
  camera.ortho_height = 42.5;
  camera.fov_y_deg = 47.0;
  saveCamera(camera, dir / "camera.json");
  const Camera loaded = loadCamera(dir / "camera.json");
  EXPECT_EQ(loaded.position, camera.position);
  EXPECT_EQ(loaded.pivot, camera.pivot);
  EXPECT_NEAR(glm::dot(loaded.orientation, camera.orientation), 1.0, 1e-15);
  EXPECT_EQ(loaded.world_up, camera.world_up);
  EXPECT_EQ(loaded.projection, Projection::Orthographic);
  EXPECT_EQ(loaded.ortho_height, 42.5);
  EXPECT_EQ(loaded.fov_y_deg, 47.0);
}

TEST(Camera, MalformedJsonNamesTheField) {
  TempDir dir;
  const auto path = dir.write("camera.json", R"({"position": [1, 2], "orientation_wxyz": [1,0,0,0],
                                                 "pivot": [0,0,0]})");
  try {
    loadCamera(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("position"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("camera.json"), std::string::npos) << e.what();
  }
}

TEST(CameraPath, PassesThroughKeyframesAndIsSmooth) {
  std::vector<CameraKeyframe> keys;
  for (int i = 0; i < 4; ++i) {
    Camera camera;
    const double angle = i * std::numbers::pi / 4;
    camera.lookAt({10 * std::cos(angle), 10 * std::sin(angle), 3}, {0, 0, 0}, {0, 0, 1});
    keys.push_back({double(i), camera});
  }
  const CameraPath path(keys);
  for (const CameraKeyframe& key : keys) {
    const Camera at = path.at(key.time);
    expectNear(at.position, key.camera.position, 1e-9);
    EXPECT_NEAR(std::abs(glm::dot(at.orientation, key.camera.orientation)), 1.0, 1e-9);
  }
  // No jumps: the step between consecutive frames of a 61-frame sequence changes gradually.
  double previous = -1, largest_change = 0, largest = 0;
  for (int f = 1; f < 61; ++f) {
    const double step = glm::length(path.frame(f, 61).position - path.frame(f - 1, 61).position);
    if (previous >= 0) largest_change = std::max(largest_change, std::abs(step - previous));
    largest = std::max(largest, step);
    previous = step;
  }
  EXPECT_LT(largest_change, 0.1 * largest);
  expectNear(path.frame(60, 61).position, keys.back().camera.position, 1e-9);
}

TEST(Frustum, CullsBoxesOutsideTheView) {
  Camera camera;
  camera.lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
  Bounds3 scene;
  scene.extend(-50, -50, -50);
  scene.extend(50, 50, 50);
  const Frustum frustum(camera.projectionMatrix(1.0, camera.clipRange(scene)) *
                        camera.viewMatrix());
  Bounds3 ahead, behind, aside;
  ahead.extend(-1, -1, -1), ahead.extend(1, 1, 1);
  behind.extend(-1, -30, -1), behind.extend(1, -20, 1);
  aside.extend(40, -1, -1), aside.extend(45, 1, 1);
  EXPECT_TRUE(frustum.intersects(ahead));
  EXPECT_FALSE(frustum.intersects(behind));
  EXPECT_FALSE(frustum.intersects(aside));
}

}  // namespace
}  // namespace parallax::test
