// Point-pairs picking in the registration preview (CloudCompare's "align (point pairs picking)"):
// a click picks a point of the source, the next its match on the target, and so on; each pair is
// numbered on both clouds (S1 and T1, ...) and can be removed; from three pairs on, the rigid
// transform they give (registration/point_pairs.h, least squares, never a reflection) moves the
// source in the preview at once, with its RMS over the pairs; Enter or the panel's Refine runs
// ICP from it (registration_panel.cpp), whose result is previewed before anything is written.
//
// Each side is uploaded on its own and a click is picked in that side alone (the renderer's pick,
// render/point_picker.h, over the side's draw set): two copies of one scan lie on each other, and
// the front-most point of both would often be the wrong cloud's. The source's layer is drawn
// moved by the fit, but its picks are read back from the source as the file holds it (the
// layer's points are the source's, in its order), so a fourth pair is picked on the moved source
// and still gives the source's own coordinates.
#include <imgui.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <optional>
#include <span>
#include <string>

#include "io/point_file.h"
#include "registration/cloud_registration.h"
#include "render/draw_set_layers.h"
#include "render/stereo.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

void reportPairs(Session& s, const std::string& message) {
  s.registration.message = message;
  std::fprintf(stderr, "parallax view: %s\n", message.c_str());
}

// The transform the source layer is drawn with: the pairs' fit once there is one.
RigidTransform shownPairTransform(const PairPicking& p) {
  return p.fit ? p.fit->transform : RigidTransform{};
}

// Uploads the source layer moved by the fit (or not at all) and the target layer if it is not
// there yet, and the set drawing both.
void uploadPairLayers(Session& s) {
  PairPicking& p = s.registration.pairs;
  if (!p.target_layer) {
    p.target_layer = std::make_unique<GpuPointCloud>(
        registrationPreviewSide(*p.target, RigidTransform{}, kPreviewTargetColor));
  }
  p.source_layer = std::make_unique<GpuPointCloud>(
      registrationPreviewSide(*p.source, shownPairTransform(p), kPreviewSourceColor));
  p.shown_set = withLayer(p.target_layer->drawSet(), p.source_layer->drawSet());
  s.drawn.reset();
}

// The fit of the complete pairs (three or more), shown at once; none below three pairs, or with
// the reason where the pairs give none.
void fitPairs(Session& s) {
  PairPicking& p = s.registration.pairs;
  const std::size_t pairs = p.target_points.size();
  const bool had_fit = p.fit.has_value();
  p.fit.reset();
  p.fit_error.clear();
  if (pairs >= 3) {
    try {
      p.fit = rigidTransformFromPairs(std::span(p.source_points.data(), pairs), p.target_points);
      char line[200];
      std::snprintf(line, sizeof line,
                    "pairs fit: rms %.9g over %zu pairs, rotation %.6g deg, translation %.6g",
                    p.fit->rms, pairs, p.fit->transform.angleDegrees(),
                    p.fit->transform.translationLength());
      reportPairs(s, line);
      logRegistrationTransform("pairs transform", p.fit->transform);
    } catch (const std::exception& e) {
      p.fit_error = e.what();
      reportPairs(s, "pairs: " + p.fit_error);
    }
  }
  if (had_fit || p.fit) uploadPairLayers(s);
}

void logPick(const char* side, std::size_t pair, const std::array<double, 3>& point) {
  std::fprintf(stderr, "parallax view: pair %zu %s point: %.17g %.17g %.17g\n", pair, side,
               point[0], point[1], point[2]);
}

}  // namespace

void startPairPicking(Session& s) {
  RegistrationSession& r = s.registration;
  PairPicking& p = r.pairs;
  if (p.active || p.target_load.valid() || r.run.valid()) return;
  if (!s.cloud_points) {
    reportPairs(s, "pairs: needs a whole cloud shown (an octree's nodes are not registered)");
    return;
  }
  const std::filesystem::path target_path = std::string(r.target_text.data());
  if (target_path.empty()) {
    reportPairs(s, "pairs: give the target file");
    return;
  }
  p.source = std::make_shared<const PointCloud>(s.cloud_points->clone());
  if (p.target && p.target_path == target_path) {
    std::promise<std::shared_ptr<const PointCloud>> ready;
    ready.set_value(p.target);
    p.target_load = ready.get_future();
  } else {
    p.target_load = std::async(std::launch::async, [target_path] {
      return std::make_shared<const PointCloud>(readPointFile(target_path));
    });
  }
  p.target_path = target_path;
  r.message = "reading " + target_path.string() + " ...";
}

void stopPairPicking(Session& s) {
  PairPicking& p = s.registration.pairs;
  p.active = false;
  s.drawn.reset();
}

void updatePairPicking(Session& s) {
  RegistrationSession& r = s.registration;
  PairPicking& p = r.pairs;
  if (r.pairs_requested && s.cloud_points) {
    r.pairs_requested = false;
    startPairPicking(s);
  }
  if (!p.target_load.valid() ||
      p.target_load.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  try {
    p.target = p.target_load.get();
    p.target_layer.reset();
    p.source_points.clear();
    p.target_points.clear();
    p.fit.reset();
    p.fit_error.clear();
    uploadPairLayers(s);
    p.active = true;
    r.shown = false;  // the pairs' layers, not an earlier ICP preview
    reportPairs(s, "pick pairs: " + p.target_path.string() + " read (" +
                       std::to_string(p.target->count) +
                       " points); click a point of the source (orange), then its match on the "
                       "target (blue)");
  } catch (const std::exception& e) {
    p.target.reset();
    reportPairs(s, std::string("pairs: ") + e.what());
  }
}

bool pairPickingTakesClicks(const Session& s) {
  const PairPicking& p = s.registration.pairs;
  return p.active && p.source_layer && p.target_layer;
}

const DrawSet* pairPickingDrawSet(const Session& s) {
  return pairPickingTakesClicks(s) ? &s.registration.pairs.shown_set : nullptr;
}

void pairPickingClick(Session& s, int x, int y, int width, int height) {
  PairPicking& p = s.registration.pairs;
  if (!pairPickingTakesClicks(s)) return;
  const bool source_side = p.source_points.size() == p.target_points.size();
  PickSource source(source_side ? *p.source : *p.target);
  DrawSet side = source_side ? p.source_layer->drawSet() : p.target_layer->drawSet();
  side.typical_spacing = p.shown_set.typical_spacing;  // the sizes drawn (the set's, the target's)
  const StereoFrame frame = stereoFrame(s.camera, s.stereo, width, height);
  PickRequest request;
  request.x = x, request.y = y;
  s.drawn.reset();  // the pick's offscreen frame is now the renderer's last picture
  const auto picked = pickPoint(*s.renderer, source, side, frame.views, frame.composition,
                                s.settings, width, height, request);
  if (!picked) {
    reportPairs(s, std::string("pairs: no point of the ") + (source_side ? "source" : "target") +
                       " under the cursor");
    return;
  }
  const std::array<double, 3> point{picked->position.x, picked->position.y, picked->position.z};
  if (source_side) {
    p.source_points.push_back(point);
    logPick("source", p.source_points.size(), point);
    s.registration.message =
        "pair " + std::to_string(p.source_points.size()) + ": now its match on the target (blue)";
  } else {
    p.target_points.push_back(point);
    logPick("target", p.target_points.size(), point);
    s.registration.message = "pair " + std::to_string(p.target_points.size()) + " picked";
    fitPairs(s);
  }
}

void removePair(Session& s, std::size_t index) {
  PairPicking& p = s.registration.pairs;
  if (index >= p.source_points.size()) return;
  p.source_points.erase(p.source_points.begin() + std::ptrdiff_t(index));
  if (index < p.target_points.size()) {
    p.target_points.erase(p.target_points.begin() + std::ptrdiff_t(index));
  }
  reportPairs(s, "pairs: removed pair " + std::to_string(index + 1) + ", " +
                     std::to_string(p.target_points.size()) + " complete");
  fitPairs(s);
}

void removeLastPick(Session& s) {
  PairPicking& p = s.registration.pairs;
  if (p.source_points.size() > p.target_points.size()) {
    p.source_points.pop_back();
    reportPairs(
        s, "pairs: removed the source point of pair " + std::to_string(p.source_points.size() + 1));
  } else if (!p.target_points.empty()) {
    p.target_points.pop_back();
    reportPairs(
        s, "pairs: removed the target point of pair " + std::to_string(p.target_points.size() + 1));
    fitPairs(s);
  }
}

void refinePairs(Session& s) {
  const PairPicking& p = s.registration.pairs;
  if (!p.fit) {
    reportPairs(s, "pairs: refine needs three pairs that give a transform");
    return;
  }
  startRegistration(s, p.fit->transform);
}

bool registrationKey(Session& s, int key, int mods) {
  if (key == GLFW_KEY_T && (mods & GLFW_MOD_CONTROL)) {
    // The panel's Accept from the keyboard (and for scripts and tests, which cannot find a
    // button).
    acceptRegistration(s);
    return true;
  }
  if (!pairPickingTakesClicks(s)) return false;
  switch (key) {
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      refinePairs(s);
      return true;
    case GLFW_KEY_BACKSPACE:
      removeLastPick(s);
      return true;
    default:
      return false;
  }
}

void appendPairOverlay(const Session& s, OverlayScene& scene) {
  const PairPicking& p = s.registration.pairs;
  if (!pairPickingTakesClicks(s)) return;
  // Markers in the clouds' colours, white labels beside them: a label in a cloud's own colour
  // would vanish over that cloud.
  constexpr OverlayColor kSourceMarker{1.0f, 140 / 255.0f, 0.0f, 1.0f};
  constexpr OverlayColor kTargetMarker{30 / 255.0f, 110 / 255.0f, 1.0f, 1.0f};
  const RigidTransform shown = shownPairTransform(p);
  for (std::size_t i = 0; i < p.source_points.size(); ++i) {
    const auto moved = shown.apply(p.source_points[i]);
    const glm::dvec3 at{moved[0], moved[1], moved[2]};
    scene.markers.push_back({at, kSourceMarker, 9.0f});
    scene.labels.push_back({at, "S" + std::to_string(i + 1), {1, 1, 1, 1}});
  }
  for (std::size_t i = 0; i < p.target_points.size(); ++i) {
    const glm::dvec3 at{p.target_points[i][0], p.target_points[i][1], p.target_points[i][2]};
    scene.markers.push_back({at, kTargetMarker, 9.0f});
    scene.labels.push_back({at, "T" + std::to_string(i + 1), {1, 1, 1, 1}});
  }
}

void drawPairPickingPanel(Session& s) {
  RegistrationSession& r = s.registration;
  PairPicking& p = r.pairs;
  if (p.target_load.valid()) {
    ImGui::TextUnformatted("reading the target ...");
    return;
  }
  if (!p.active) {
    if (!r.run.valid() && ImGui::Button("Pick point pairs")) startPairPicking(s);
    return;
  }
  if (ImGui::Button("Stop picking pairs")) stopPairPicking(s);
  const bool source_next = p.source_points.size() == p.target_points.size();
  ImGui::Text("click: a point of the %s (Backspace: undo the last)",
              source_next ? "source (orange)" : "target (blue)");
  std::optional<std::size_t> remove;
  for (std::size_t i = 0; i < p.source_points.size(); ++i) {
    ImGui::PushID(int(i));
    const auto& a = p.source_points[i];
    if (i < p.target_points.size()) {
      const auto& b = p.target_points[i];
      ImGui::Text("%zu: (%.3f %.3f %.3f) -> (%.3f %.3f %.3f)", i + 1, a[0], a[1], a[2], b[0], b[1],
                  b[2]);
      if (p.fit) {
        const auto moved = p.fit->transform.apply(a);
        const double dx = moved[0] - b[0], dy = moved[1] - b[1], dz = moved[2] - b[2];
        ImGui::SameLine();
        ImGui::Text("residual %.4g", std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    } else {
      ImGui::Text("%zu: (%.3f %.3f %.3f) -> ?", i + 1, a[0], a[1], a[2]);
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("remove")) remove = i;
    ImGui::PopID();
  }
  if (remove) removePair(s, *remove);
  if (p.fit) {
    ImGui::Text("from the pairs: rms %.6g, rotation %.6g deg, translation %.6g", p.fit->rms,
                p.fit->transform.angleDegrees(), p.fit->transform.translationLength());
    if (!r.run.valid() && ImGui::Button("Refine (ICP from the pairs' transform; Enter)")) {
      refinePairs(s);
    }
  } else if (!p.fit_error.empty()) {
    ImGui::TextWrapped("%s", p.fit_error.c_str());
  } else {
    ImGui::Text("%zu of 3 pairs", p.target_points.size());
  }
}

}  // namespace parallax::viewer_internal
