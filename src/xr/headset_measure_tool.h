// The measurement tools in the headset (issue 24, item 4): the laser's picks make points,
// distances, heights, areas, angles and profiles. They are the window's Measurement kinds, with
// its arithmetic, its printed line and its labels (measure/measurement.h,
// measure/measurement_overlay.h); this class only decides which picks make which measurement, as
// the window's measure_tool.cpp does for clicks.
//
// The controls (a headset has no Enter key and no panel):
//   trigger       adds the laser's point to the measurement being drawn. Every kind but the area
//                 finishes at its least number of points: a point at one, a distance, a height
//                 and a profile's section line at two, an angle at three (a distance here is one
//                 segment, a profile one straight section).
//   tool button   (B, or Y on a left Touch controller; a short press, see locomotion.h) closes an
//                 area that has three or more points; otherwise it drops what is being drawn and
//                 selects the next tool, in the window's order: distance -> height -> area ->
//                 angle -> profile -> point -> distance.
//   held          (the tool button held kLongPressSeconds) deletes the measurement under that
//                 hand's laser (measurementUnderLaser), or the last one when the laser is on none:
//                 the caller's document, not this class's (xr_view.cpp).
//   trigger on a  (a press with a finished measurement's vertex under the laser, within
//   vertex        kVertexConeDeg: vertexUnderLaser) grabs that vertex instead of picking; while
//                 the trigger is held the caller moves it to the laser's pick of every later
//                 frame (drag), and letting go leaves it at the last one (release). A press starts
//                 a new pick only when no vertex is under the laser.
//   trigger on a  (a press with no vertex under the laser but a line of a finished distance or
//   line          area within kVertexConeDeg: segmentUnderLaser) adds a vertex there, between
//                 the line's two, at the laser's pick on the cloud (or, when it hits nothing, the
//                 line's closest point to the ray), and grabs it at once (insert): it follows the
//                 laser as a grabbed vertex does. Only kinds whose vertex count is free
//                 (vertexCountIsFree); a press on another kind's line picks.
//   tool button   (pressed while that hand's trigger holds a vertex; it acts at the press, and
//   on a held     that press is then nothing else: Locomotion::claimToolPress) removes the held
//   vertex        vertex when its measurement keeps at least minimumVertices of its kind
//                 (removeHeld); otherwise the vertex stays, still held.
// Positions are the cloud's file coordinates in double, as everywhere in measure/.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "measure/measurement.h"

namespace parallax {

// A laser in file coordinates: from `origin` along `direction` (any length but zero). The stage
// mapping is a rotation and a uniform scale, so angles about the ray are the stage's.
struct LaserRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};
};

// The half-angle about the laser within which a vertex or a measurement's line is under it: half
// the laser picker's cone (xr_view.cpp's 2 degrees), about 10 pixels of a 20-pixel-a-degree
// headset. Smaller is hard to hold on a vertex with a hand-held laser; larger keeps a new pick
// from starting near a vertex (a press there grabs it): 0.5 degrees is 9 cm at 10 m.
constexpr double kVertexConeDeg = 0.5;

// A vertex of one of a document's measurements: their indices.
struct MeasurementVertex {
  std::size_t measurement = 0;
  std::size_t vertex = 0;
  bool operator==(const MeasurementVertex&) const = default;
};

// The vertex of `measurements` under the laser: of those in front of its origin within
// `cone_deg` of the ray, the one at the least angle (on a tie within 1e-9 of the angle's tangent,
// a rounding's worth, the nearer to the origin, then the first in the list); none when no vertex
// is.
std::optional<MeasurementVertex> vertexUnderLaser(std::span<const Measurement> measurements,
                                                  const LaserRay& ray,
                                                  double cone_deg = kVertexConeDeg);

// The measurement under the laser: the one of vertexUnderLaser when there is one, else the one
// whose lines (the segments between its vertices, an area's closing one too) come closest in
// angle to the ray within `cone_deg` (the first in the list on a tie); none when none does.
std::optional<std::size_t> measurementUnderLaser(std::span<const Measurement> measurements,
                                                 const LaserRay& ray,
                                                 double cone_deg = kVertexConeDeg);

// True for the kinds whose vertices the headset adds and removes: distance (a polyline) and area.
// Not point, height and angle (an exact count) nor profile (a straight section in the headset).
bool vertexCountIsFree(MeasurementKind kind);

// A line of a measurement under the laser: between its vertices `segment` and `segment + 1` (an
// area's closing line: the last and 0), and its point closest to the ray (file coordinates).
struct MeasurementSegment {
  std::size_t measurement = 0;
  std::size_t segment = 0;
  glm::dvec3 closest{0.0};
};

// The line of a distance or an area (vertexCountIsFree) that comes closest in angle to the ray
// within `cone_deg`, as measurementUnderLaser measures lines (the first in the list on a tie,
// then the first line); none when none does. It does not look at vertices: a caller asks
// vertexUnderLaser first. `closest` is the line's point nearest the ray (the half-line from the
// origin) in 3D distance.
std::optional<MeasurementSegment> segmentUnderLaser(std::span<const Measurement> measurements,
                                                    const LaserRay& ray,
                                                    double cone_deg = kVertexConeDeg);

// What removeHeld did: the vertex, and whether it left (false: its measurement is at its kind's
// minimumVertices, and it stays, still held).
struct VertexRemoval {
  MeasurementVertex vertex;
  bool removed = false;
};

class HeadsetMeasureTool {
 public:
  // `profile_width`: the corridor's full width of the profiles it makes (view's --profile-width).
  explicit HeadsetMeasureTool(double profile_width = 1.0) : profile_width_(profile_width) {}

  // The tool the trigger uses.
  MeasurementKind kind() const { return current_.kind; }
  // The measurement being drawn (its kind is the tool's); no points when none is.
  const Measurement& inProgress() const { return current_; }

  // Adds a picked point; returns the measurement when this point finishes it.
  std::optional<Measurement> pick(const glm::dvec3& point);
  // The tool button: returns the area it closes, or std::nullopt when it selected the next tool.
  std::optional<Measurement> toolButton();

  // Moving a vertex, one grab a hand (`hand` 0 or 1, xr_input.h's XrHandIndex).
  // The trigger went down on `hand`: grabs the vertex of `measurements` under its laser (a grab
  // the other hand held of the same vertex passes to this one) and returns it; none when no
  // vertex is under the laser, and then the press is a pick.
  std::optional<MeasurementVertex> grab(int hand, std::span<const Measurement> measurements,
                                        const LaserRay& ray);
  // The vertex `hand` holds; none when it holds none.
  std::optional<MeasurementVertex> grabbed(int hand) const;
  // The laser's pick while `hand`'s trigger is held: the vertex it holds goes to `point`, in
  // `measurements` itself (the value and labels follow it). Returns the vertex moved, none when
  // the hand holds none.
  std::optional<MeasurementVertex> drag(int hand, std::vector<Measurement>& measurements,
                                        const glm::dvec3& point);
  // `hand`'s trigger let go: its grab ends, the vertex where the last drag left it. Returns the
  // vertex it held.
  std::optional<MeasurementVertex> release(int hand);
  // Measurement `index` left the document: a grab of it ends, the grabs of later ones follow
  // their measurement's new index.
  void erased(std::size_t index);

  // Adding and removing vertices of finished distances and areas (vertexCountIsFree).
  // The trigger went down on `hand` over `segment` (segmentUnderLaser of `measurements`): a
  // vertex goes in at `point`, between the segment's two (index segment + 1), and `hand` holds
  // it, as grab() would; another hand's grab of a later vertex of it follows its new index.
  // Returns the new vertex.
  MeasurementVertex insert(int hand, std::vector<Measurement>& measurements,
                           const MeasurementSegment& segment, const glm::dvec3& point);
  // True while the vertex `hand` holds is one that insert() added (until the release).
  bool holdsInserted(int hand) const;
  // The tool button pressed while `hand` holds a vertex: it leaves its measurement when that
  // keeps at least minimumVertices of its kind (a distance 2, an area 3) and the kind's count is
  // free, and the grab ends (the other hand's grab of a later vertex follows its new index);
  // otherwise it stays, held. None when the hand holds nothing.
  std::optional<VertexRemoval> removeHeld(int hand, std::vector<Measurement>& measurements);

 private:
  double profile_width_;
  std::array<std::optional<MeasurementVertex>, 2> grabbed_;
  std::array<bool, 2> inserted_{false, false};  // the grab is of a vertex insert() added
  Measurement current_{.kind = MeasurementKind::Distance};
};

}  // namespace parallax
