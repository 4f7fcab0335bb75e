// The measurement tools' logic: clicks add picked points, keys finish, cancel and edit, the
// overlay follows the document, annotations fly the camera, profiles are extracted and exported.
// The panel that drives it is measure_panel.cpp.
#include "viewer/measure_tool.h"

#include <array>
#include <cstdio>
#include <filesystem>

#include "measure/measurement_overlay.h"
#include "viewer/viewer_session.h"

namespace parallax {

namespace {

constexpr std::array<std::pair<MeasureTool, std::string_view>, 8> kToolNames{{
    {MeasureTool::None, "none"},
    {MeasureTool::Point, "point"},
    {MeasureTool::Distance, "distance"},
    {MeasureTool::Height, "height"},
    {MeasureTool::Area, "area"},
    {MeasureTool::Angle, "angle"},
    {MeasureTool::Profile, "profile"},
    {MeasureTool::Annotation, "annotation"},
}};

constexpr double kFlightSeconds = 1.0;

}  // namespace

std::string_view measureToolName(MeasureTool tool) {
  for (const auto& [t, name] : kToolNames) {
    if (t == tool) return name;
  }
  return "none";
}

std::optional<MeasureTool> measureToolFromName(std::string_view name) {
  for (const auto& [t, n] : kToolNames) {
    if (n == name) return t;
  }
  return std::nullopt;
}

namespace viewer_internal {

namespace {

std::optional<MeasurementKind> kindOf(MeasureTool tool) {
  switch (tool) {
    case MeasureTool::Point:
      return MeasurementKind::Point;
    case MeasureTool::Distance:
      return MeasurementKind::Distance;
    case MeasureTool::Height:
      return MeasurementKind::Height;
    case MeasureTool::Area:
      return MeasurementKind::Area;
    case MeasureTool::Angle:
      return MeasurementKind::Angle;
    case MeasureTool::Profile:
      return MeasurementKind::Profile;
    case MeasureTool::None:
    case MeasureTool::Annotation:
      break;
  }
  return std::nullopt;
}

void report(Session& s, const std::string& text) {
  s.status = text;
  std::fprintf(stderr, "parallax view: %s\n", text.c_str());
}

std::string exact(const glm::dvec3& p) {
  return formatAttributeValue(p.x) + " " + formatAttributeValue(p.y) + " " +
         formatAttributeValue(p.z);
}

}  // namespace

void setMeasureTool(Session& s, MeasureTool tool) {
  MeasureSession& m = s.measure;
  if (!m.current.points.empty() || m.editing) cancelMeasurement(s);
  m.tool = tool;
  if (const auto kind = kindOf(tool)) m.current = Measurement{.kind = *kind};
  s.status = "tool: " + std::string(measureToolName(tool));
}

void measureClick(Session& s, const PickResult& picked) {
  MeasureSession& m = s.measure;
  if (m.tool == MeasureTool::Annotation) {
    Annotation a;
    a.label = m.annotation_label.empty()
                  ? "Annotation " + std::to_string(m.document.annotations.size() + 1)
                  : m.annotation_label;
    a.position = picked.position;
    if (m.annotation_camera) a.camera = s.camera;
    m.document.annotations.push_back(a);
    m.annotation_label.clear();
    report(s, "annotation '" + a.label + "' at " + exact(a.position));
    return;
  }
  const auto kind = kindOf(m.tool);
  if (!kind) return;
  if (m.current.kind != *kind) m.current = Measurement{.kind = *kind};
  if (hasFixedVertexCount(*kind) && m.current.points.size() >= minimumVertices(*kind)) {
    // (Editing one: it has all its vertices; a new one goes in place of a removed one.)
    s.status = "a " + std::string(measurementKindName(*kind)) + " has " +
               std::to_string(minimumVertices(*kind)) +
               " points: remove one first (Backspace, or x in the panel)";
    return;
  }
  m.current.points.push_back(picked.position);
  std::fprintf(stderr, "parallax view: %s point %zu: %s\n",
               std::string(measurementKindName(*kind)).c_str(), m.current.points.size(),
               exact(picked.position).c_str());
  // Point, height and angle have a fixed number of vertices: they finish themselves.
  if (hasFixedVertexCount(*kind) && m.current.points.size() == minimumVertices(*kind)) {
    finishMeasurement(s);
  } else {
    s.status = describeMeasurement(m.current) + ": Enter finishes, Backspace removes the last";
  }
}

void finishMeasurement(Session& s) {
  MeasureSession& m = s.measure;
  Measurement& c = m.current;
  if (c.points.empty()) return;
  if (c.points.size() < minimumVertices(c.kind)) {
    s.status = "a " + std::string(measurementKindName(c.kind)) + " needs " +
               (hasFixedVertexCount(c.kind) ? "" : "at least ") +
               std::to_string(minimumVertices(c.kind)) + " points";
    return;
  }
  if (m.editing && *m.editing <= m.document.measurements.size()) {
    // Back where it was in the list, under its name and width.
    c.name = m.editing_original.name;
    c.profile_width = m.editing_original.profile_width;
    m.document.measurements.insert(m.document.measurements.begin() + std::ptrdiff_t(*m.editing), c);
    m.selected = *m.editing;
    m.editing.reset();
  } else {
    if (c.kind == MeasurementKind::Profile) c.profile_width = m.profile_width;
    m.document.measurements.push_back(c);
    m.selected = m.document.measurements.size() - 1;
  }
  // Six decimals on stderr (micrometres in metres): what scripts and tests compare.
  report(s, describeMeasurement(c, 6));
  c = Measurement{.kind = c.kind};
  // A finished profile is extracted at once, for the panel's plot.
  if (m.document.measurements[*m.selected].kind == MeasurementKind::Profile) selectedProfile(s);
}

void cancelMeasurement(Session& s) {
  MeasureSession& m = s.measure;
  if (m.editing && *m.editing <= m.document.measurements.size()) {
    // An edit cancelled gives the measurement back unchanged.
    m.document.measurements.insert(m.document.measurements.begin() + std::ptrdiff_t(*m.editing),
                                   m.editing_original);
    m.selected = *m.editing;
    m.editing.reset();
    m.current.points.clear();
    s.status = "edit cancelled";
    return;
  }
  m.current.points.clear();
  s.status = "measurement cancelled";
}

void editSelectedMeasurement(Session& s) {
  MeasureSession& m = s.measure;
  if (!m.selected || *m.selected >= m.document.measurements.size()) return;
  std::size_t index = *m.selected;
  if (!m.current.points.empty() || m.editing) {
    // Cancelling an edit puts that measurement back in its place, moving the ones after it.
    if (m.editing && *m.editing <= index) ++index;
    cancelMeasurement(s);
  }
  const Measurement measurement = m.document.measurements[index];
  static constexpr std::array<std::pair<MeasurementKind, MeasureTool>, 6> kToolOf{{
      {MeasurementKind::Point, MeasureTool::Point},
      {MeasurementKind::Distance, MeasureTool::Distance},
      {MeasurementKind::Height, MeasureTool::Height},
      {MeasurementKind::Area, MeasureTool::Area},
      {MeasurementKind::Angle, MeasureTool::Angle},
      {MeasurementKind::Profile, MeasureTool::Profile},
  }};
  for (const auto& [kind, tool] : kToolOf) {
    if (kind == measurement.kind) m.tool = tool;
  }
  m.document.measurements.erase(m.document.measurements.begin() + std::ptrdiff_t(index));
  m.editing = index;
  m.editing_original = measurement;
  m.current = measurement;
  m.selected.reset();
  m.profile.reset();
  s.status = "editing: click to add points, Backspace removes the last, Enter finishes";
}

void removeMeasurePoint(Session& s, std::size_t index) {
  auto& points = s.measure.current.points;
  if (index < points.size()) points.erase(points.begin() + std::ptrdiff_t(index));
}

void removeLastMeasurePoint(Session& s) {
  auto& points = s.measure.current.points;
  if (!points.empty()) points.pop_back();
}

void deleteSelectedMeasurement(Session& s) {
  MeasureSession& m = s.measure;
  if (!m.selected || *m.selected >= m.document.measurements.size()) return;
  m.document.measurements.erase(m.document.measurements.begin() + std::ptrdiff_t(*m.selected));
  m.selected.reset();
  m.profile.reset();
  s.status = "measurement deleted";
}

bool measureKey(Session& s, int key, int mods) {
  MeasureSession& m = s.measure;
  const bool drawing = !m.current.points.empty() || m.editing;
  if (key == GLFW_KEY_S && (mods & GLFW_MOD_CONTROL)) {
    saveMeasurements(s);
    return true;
  }
  if (key == GLFW_KEY_E && (mods & GLFW_MOD_CONTROL)) {
    editSelectedMeasurement(s);
    return true;
  }
  if (key == GLFW_KEY_V && (mods & GLFW_MOD_CONTROL)) {
    computeSelectedVolume(s);  // the Volume part's button (scripts and tests cannot find it)
    return true;
  }
  if (key == GLFW_KEY_X && (mods & GLFW_MOD_CONTROL)) {
    // The panel's Export buttons from the keyboard (and for scripts and tests, which cannot
    // find a button): the selected profile, CSV, or LAS with Shift.
    exportProfile(s, (mods & GLFW_MOD_SHIFT) != 0);
    return true;
  }
  switch (key) {
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      finishMeasurement(s);
      return drawing;
    case GLFW_KEY_ESCAPE:
      if (!drawing) return false;  // nothing to cancel: Escape quits, as ever
      cancelMeasurement(s);
      return true;
    case GLFW_KEY_BACKSPACE:
      removeLastMeasurePoint(s);
      return drawing;
    case GLFW_KEY_DELETE:
      deleteSelectedMeasurement(s);
      return true;
    default:
      return false;
  }
}

void flyToAnnotation(Session& s, const Annotation& a) {
  Camera target = s.camera;
  if (a.camera) {
    target = *a.camera;
  } else {
    // No saved camera: the same direction and distance, looking at the point.
    const double distance = s.camera.pivotDepth();
    target.pivot = a.position;
    target.position = a.position - s.camera.forward() * distance;
  }
  // A flight keeps the session's projection kind; a saved camera brings its own field of view.
  s.measure.flight = CameraPath({{0.0, s.camera}, {kFlightSeconds, target}});
  s.measure.flight_start = glfwGetTime();
  report(s, "flying to '" + a.label + "'");
}

bool updateMeasureFlight(Session& s) {
  MeasureSession& m = s.measure;
  if (!m.flight) return false;
  const double t = glfwGetTime() - m.flight_start;
  s.camera = m.flight->at(std::min(t, kFlightSeconds));
  if (t >= kFlightSeconds) m.flight.reset();
  return true;
}

void updateOverlay(Session& s) {
  OverlayScene scene;
  MeasurementOverlayOptions options;
  options.in_progress = s.measure.current.points.empty() ? nullptr : &s.measure.current;
  options.selected = s.measure.selected;
  appendMeasurementOverlay(s.measure.document, options, scene);
  appendClipBoxOutline(s, scene);
  appendPairOverlay(s, scene);
  s.renderer->setOverlay(std::move(scene));
}

const MeasureSession::Profile* selectedProfile(Session& s) {
  MeasureSession& m = s.measure;
  if (!m.selected || *m.selected >= m.document.measurements.size()) return nullptr;
  const Measurement& measurement = m.document.measurements[*m.selected];
  if (measurement.kind != MeasurementKind::Profile) return nullptr;
  if (m.profile && m.profile->measurement == *m.selected && m.profile->of == measurement) {
    return &*m.profile;
  }
  MeasureSession::Profile profile;
  profile.measurement = *m.selected;
  profile.of = measurement;
  try {
    if (s.cloud_points) {
      completeCloud(s);  // (the profile's points carry every attribute, as an octree's do)
      profile.profile =
          extractProfile(*s.cloud_points, measurement.points, measurement.profile_width);
      profile.source = s.build ? "the preview (a sample of the file)" : "every point of the file";
    } else if (s.octree) {
      // Every node the corridor meets, at full detail (not the level drawn).
      profile.profile = extractProfile(*s.octree, measurement.points, measurement.profile_width);
      profile.source = "every point of the octree";
    } else {
      profile.error = "no cloud open";
    }
  } catch (const std::exception& e) {
    profile.error = e.what();
  }
  if (profile.error.empty()) {
    std::fprintf(stderr, "parallax view: profile of measurement %zu: %zu points from %s\n",
                 profile.measurement + 1, profile.profile.samples.size(), profile.source.c_str());
  } else {
    std::fprintf(stderr, "parallax view: no profile of measurement %zu: %s\n",
                 profile.measurement + 1, profile.error.c_str());
  }
  m.profile = std::move(profile);
  return &*m.profile;
}

void exportProfile(Session& s, bool las) {
  const MeasureSession::Profile* profile = selectedProfile(s);
  if (!profile || !profile->error.empty()) return;
  const auto path =
      s.options->screenshot_dir /
      ("profile-" + std::to_string(profile->measurement + 1) + (las ? ".las" : ".csv"));
  try {
    if (las) {
      writeProfileLas(profile->profile, path);
    } else {
      writeProfileCsv(profile->profile, path);
    }
    report(s, "profile written to " + std::filesystem::absolute(path).string() + " (" +
                  std::to_string(profile->profile.samples.size()) + " points)");
  } catch (const std::exception& e) {
    report(s, std::string("cannot export the profile: ") + e.what());
  }
}

void saveMeasurements(Session& s) {
  MeasurementDocument document = s.measure.document;
  document.camera = s.camera;
  try {
    saveMeasurementDocument(document, s.measure.file);
    report(s, "measurements saved to " + s.measure.file);
  } catch (const std::exception& e) {
    report(s, std::string("cannot save the measurements: ") + e.what());
  }
}

void loadMeasurements(Session& s) {
  try {
    MeasurementDocument document = loadMeasurementDocument(s.measure.file);
    if (document.camera) s.camera = *document.camera;
    s.measure.document = std::move(document);
    s.measure.selected.reset();
    s.measure.profile.reset();
    report(s, "measurements loaded from " + s.measure.file + " (" +
                  std::to_string(s.measure.document.measurements.size()) + " measurements, " +
                  std::to_string(s.measure.document.annotations.size()) + " annotations)");
  } catch (const std::exception& e) {
    report(s, std::string("cannot load the measurements: ") + e.what());
  }
}

}  // namespace viewer_internal
}  // namespace parallax
