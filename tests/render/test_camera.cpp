// Camera unit tests: no GL needed.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

#include "core/error.h"
#include "render/camera.h"
#include "render/camera_path.h"
#include "render/frustum.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
  camera.orbit(kPi / 2, 0.0, OrbitMode::Turntable);
  expectNear(camera.forward(), {0, 0, -1}, 1e-9);
  EXPECT_NEAR(glm::dot(right_before, camera.right()), 0.0, 1e-9);
  // And pitching back leaves the pole on the side the yaw chose.
  camera.orbit(0.0, kPi / 4, OrbitMode::Turntable);
  EXPECT_TRUE(finite(camera.position));
  EXPECT_NEAR(glm::length(camera.position), 10.0, 1e-9);
  EXPECT_NEAR(glm::dot(camera.forward(), glm::dvec3(0, 0, 1)), -std::sin(kPi / 4), 1e-9);
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
  for (int i = 0; i < 8; ++i) camera.orbit(0.0, -kPi / 8, OrbitMode::Free);  // half a turn
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
    const double angle = i * kPi / 4;
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
