#include "xr/profile_panel.h"

#include <algorithm>
#include <cassert>
#include <memory>

#include "measure/measurement.h"

namespace parallax {

std::array<glm::dvec3, 4> profilePanelCorners(const std::vector<glm::dvec3>& line,
                                              const glm::dvec3& head, double aspect) {
  assert(line.size() >= 2 && "profilePanelCorners: a section line has two or more vertices");
  const glm::dvec3 middle = 0.5 * (line.front() + line.back());
  double top = line.front().z;
  for (const glm::dvec3& p : line) top = std::max(top, p.z);
  double distance = glm::length(head - middle);
  if (!(distance > 1e-9)) distance = 1.0;  // the head in the line's middle: any size will do
  // Towards the head on the ground; straight above the line: the line's left normal; a line
  // with no horizontal extent under the head: north.
  glm::dvec2 facing(head.x - middle.x, head.y - middle.y);
  if (!(glm::length(facing) > 1e-9 * distance)) {
    const glm::dvec2 along(line.back().x - line.front().x, line.back().y - line.front().y);
    facing = glm::length(along) > 0 ? glm::dvec2(-along.y, along.x) : glm::dvec2(0, 1);
  }
  facing = glm::normalize(facing);
  // Seen from the head (looking along -facing, z up), right is up x facing.
  const glm::dvec3 right(-facing.y, facing.x, 0.0), up(0.0, 0.0, 1.0);
  const double width = kProfilePanelWidthPerDistance * distance, height = width * aspect;
  const glm::dvec3 bottom(middle.x, middle.y, top + kProfilePanelLift * distance);
  const glm::dvec3 bottom_left = bottom - 0.5 * width * right;
  const glm::dvec3 bottom_right = bottom + 0.5 * width * right;
  return {bottom_left, bottom_right, bottom_right + height * up, bottom_left + height * up};
}

OverlayImage profilePanel(const HeightProfile& profile, const std::vector<glm::dvec3>& line,
                          const glm::dvec3& head, std::string_view title, const OverlayFont& font,
                          const ProfilePlotLayout& layout) {
  // A section line with no horizontal extent has no stations (and no points): any axis will do.
  const double length = horizontalLength(line);
  ProfilePlotImage plot = drawProfilePlot(profile, length > 0 ? length : 1.0, title, font, layout);
  OverlayImage panel;
  panel.width = plot.width;
  panel.height = plot.height;
  panel.corners = profilePanelCorners(line, head, double(plot.height) / double(plot.width));
  panel.rgba = std::make_shared<const std::vector<std::uint8_t>>(std::move(plot.rgba));
  return panel;
}

}  // namespace parallax
