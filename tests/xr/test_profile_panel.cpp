// Where the profile's panel stands (xr/profile_panel.h), against the rule written out here: above
// the line's middle, 0.05 D over its higher end, 0.5 D wide, upright, facing the head across the
// ground (the line's left normal when the head is straight above its middle).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "xr/profile_panel.h"

namespace parallax {
namespace {

void expectNear(const glm::dvec3& a, const glm::dvec3& b, const char* what) {
  EXPECT_NEAR(a.x, b.x, 1e-9) << what;
  EXPECT_NEAR(a.y, b.y, 1e-9) << what;
  EXPECT_NEAR(a.z, b.z, 1e-9) << what;
}

TEST(ProfilePanel, StandsAboveTheLinesMiddleFacingTheHead) {
  // A line along +x at UTM coordinates, rising 2 m; the head 6 m south of its middle and 8 m
  // below it: D = 10.
  const glm::dvec3 start(512000.0, 5400000.0, 300.0), end(512004.0, 5400000.0, 302.0);
  const glm::dvec3 middle(512002.0, 5400000.0, 301.0);
  const glm::dvec3 head = middle + glm::dvec3(0.0, -6.0, -8.0);
  const auto c = profilePanelCorners({start, end}, head, 0.625);
  // Seen from the south, right is east (+x); 5 wide, 3.125 high, bottom 0.5 over z 302.
  expectNear(c[0], {512002.0 - 2.5, 5400000.0, 302.5}, "bottom-left");
  expectNear(c[1], {512002.0 + 2.5, 5400000.0, 302.5}, "bottom-right");
  expectNear(c[2], {512002.0 + 2.5, 5400000.0, 305.625}, "top-right");
  expectNear(c[3], {512002.0 - 2.5, 5400000.0, 305.625}, "top-left");

  // The head north-east of the middle, 3 and 4 m away across the ground, level with it (D = 5):
  // the panel faces (0.6, 0.8); right, seen from there, is (-0.8, 0.6).
  const auto d = profilePanelCorners({start, end}, middle + glm::dvec3(3.0, 4.0, 0.0), 0.5);
  const glm::dvec3 right(-0.8, 0.6, 0.0);
  const glm::dvec3 bottom(512002.0, 5400000.0, 302.25);
  expectNear(d[0], bottom - 1.25 * right, "bottom-left, north-east");
  expectNear(d[1], bottom + 1.25 * right, "bottom-right, north-east");
  expectNear(d[2], bottom + 1.25 * right + glm::dvec3(0, 0, 1.25), "top-right, north-east");
}

TEST(ProfilePanel, AHeadStraightAboveTheMiddleFacesTheLinesLeft) {
  const glm::dvec3 start(0.0, 0.0, 0.0), end(0.0, 10.0, 0.0);  // northwards
  const auto c = profilePanelCorners({start, end}, {0.0, 5.0, 4.0}, 0.5);
  // Facing west (the line's left, (-1, 0)); right seen from the west is south (0, -1).
  expectNear(c[0], {0.0, 5.0 + 1.0, 0.2}, "bottom-left");
  expectNear(c[1], {0.0, 5.0 - 1.0, 0.2}, "bottom-right");
  expectNear(c[3], {0.0, 5.0 + 1.0, 1.2}, "top-left");
}

}  // namespace
}  // namespace parallax
