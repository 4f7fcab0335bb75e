// A profile's plot on a panel in the headset (issue 24): the picture of measure/
// profile_plot_image.h on a quad standing in the scene above the section line, drawn by the
// overlay pass in each eye at its depth (render/overlay.h OverlayImage), like the line and its
// labels.
//
// Where it stands (file coordinates, z up; the world only ever turns about the vertical, so the
// panel stays upright whatever the controllers do):
//   - above the middle of the section line (the midpoint of its first and last vertices), its
//     bottom edge kProfilePanelLift x D above the line's highest vertex, so it hides neither the
//     line nor the labels at its vertices;
//   - facing the head where it was when the profile was made: the panel's normal is the
//     horizontal direction from that midpoint to the head (the line's left normal when the head
//     is straight above it), its right edge to the right as seen from there;
//   - kProfilePanelWidthPerDistance x D wide (about 28 degrees seen from the head: readable where
//     it was made, as a screen at arm's length is; it scales with the world, as the line does),
//     and as high as the picture's aspect makes it;
// where D is the distance from the head to the line's midpoint, in file units.
// Why in the scene and not on the left controller: the plot is read against the section it
// draws, and standing above that section it is found where the profile was made, in each eye at
// its depth like the other measurements; a panel on a hand would move with every gesture (the
// hands grab, fly and point) and hide the laser's targets. Why facing the head of that moment
// and not every frame: a panel turning with the head would swim against the fixed scene.
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "measure/height_profile.h"
#include "measure/profile_plot_image.h"
#include "render/overlay.h"

namespace parallax {

inline constexpr double kProfilePanelWidthPerDistance = 0.5;
inline constexpr double kProfilePanelLift = 0.05;

// The panel's corners for the section `line` (two or more vertices, file coordinates) seen from
// `head` (file coordinates), for a picture `aspect` = height / width: bottom-left, bottom-right,
// top-right, top-left as OverlayImage wants them.
std::array<glm::dvec3, 4> profilePanelCorners(const std::vector<glm::dvec3>& line,
                                              const glm::dvec3& head, double aspect);

// The panel of `profile`, extracted along `line`: its plot (the section's horizontal length as
// the distance axis, `title` at the top) at profilePanelCorners.
OverlayImage profilePanel(const HeightProfile& profile, const std::vector<glm::dvec3>& line,
                          const glm::dvec3& head, std::string_view title, const OverlayFont& font,
                          const ProfilePlotLayout& layout = {});

}  // namespace parallax
