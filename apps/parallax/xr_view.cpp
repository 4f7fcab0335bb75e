#include "xr_view.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "filter_options.h"
#include "measure/height_profile.h"
#include "measure/measurement.h"
#include "measure/measurement_document.h"
#include "measure/measurement_overlay.h"
#include "render/gl_context.h"
#include "render/overlay_font.h"
#include "render/point_picker.h"
#include "render/renderer.h"
#include "render_scene.h"
#include "viewer/xr_mirror_window.h"
#include "xr/comfort_vignette.h"
#include "xr/frame_budget.h"
#include "xr/headset_measure_tool.h"
#include "xr/locomotion.h"
#include "xr/profile_panel.h"
#include "xr/stage_mapping.h"
#include "xr/xr_headset.h"

namespace parallax::cli {
namespace {

// The laser picks what a narrow camera along the aim ray sees at its centre: the front-most
// point within kLaserConeDeg / 2 of the ray (render/point_picker.h, exact source values).
constexpr int kLaserPixels = 33;
constexpr double kLaserConeDeg = 2.0;
constexpr double kLaserLength = 5.0;  // stage metres drawn from the hand
const OverlayColor kLaserColor{1.0f, 0.2f, 0.2f, 0.9f};

// A profile made in the headset: what the window's panel says of it beside its plot (how many
// points, from what), and the heights it spans, as a label at the section line's start; the plot
// itself on a panel above the line (xr/profile_panel.h).
struct HeadsetProfileSummary {
  std::size_t measurement = 0;  // its index in the document
  glm::dvec3 anchor{0.0};
  std::string text;
  OverlayImage panel;
};

View laserView(const StagePlacement& placement, const StagePose& aim) {
  View view;
  view.viewport = {0, 0, kLaserPixels, kLaserPixels};
  view.camera = cameraAtStagePose(placement, aim);
  view.camera.fov_y_deg = kLaserConeDeg;
  return view;
}

// A hand's aim as a ray in file coordinates (the laser's origin and direction).
LaserRay laserRay(const StagePlacement& placement, const StagePose& aim) {
  return {stageToFile(placement, aim.position),
          stageToFileVector(placement, aim.orientation * glm::dvec3(0, 0, -1))};
}

// The lasers of the tracked hands, from the aim's position along its -z, the tool's name at each
// hand (in its kind's colour), and the measurements with their labels, the one being drawn
// brighter: lines and text in file coordinates that the overlay pass draws in each eye at its
// depth, as the window draws them.
OverlayScene laserOverlay(const StagePlacement& placement, const XrInput* input,
                          const MeasurementDocument& document, const HeadsetMeasureTool& tool,
                          const std::vector<HeadsetProfileSummary>& profiles) {
  OverlayScene scene;
  MeasurementOverlayOptions options;
  if (!tool.inProgress().points.empty()) options.in_progress = &tool.inProgress();
  // A measurement whose vertex a hand moves is drawn wider, as the window's selected one.
  for (int h = 0; h < 2; ++h) {
    if (const auto grabbed = tool.grabbed(h)) options.selected = grabbed->measurement;
  }
  appendMeasurementOverlay(document, options, scene);
  for (const HeadsetProfileSummary& profile : profiles) {
    // A profile being changed has no summary until its new one is extracted at the release.
    if (options.selected == profile.measurement) continue;
    scene.labels.push_back({profile.anchor, profile.text, {1, 1, 1, 1}});  // as its other labels
    scene.images.push_back(profile.panel);
  }
  if (!input) return scene;
  for (const XrHandInput& hand : input->hands) {
    if (!hand.tracked) continue;
    const glm::dvec3 end =
        hand.aim.position + hand.aim.orientation * glm::dvec3(0, 0, -kLaserLength);
    OverlayPolyline line;
    line.points = {stageToFile(placement, hand.aim.position), stageToFile(placement, end)};
    line.color = kLaserColor;
    scene.polylines.push_back(std::move(line));
    scene.labels.push_back({stageToFile(placement, hand.aim.position),
                            std::string(measurementKindName(tool.kind())),
                            measurementColor(tool.kind())});
  }
  return scene;
}

}  // namespace

bool xrViewAvailable() {
  return true;
}

int runXrView(const XrViewOptions& o) {
  if (!o.origin.empty() && o.origin.size() != 3) {
    throw std::invalid_argument("--xr-origin: expected X,Y,Z (three numbers)");
  }
  if (o.scale < 0) throw std::invalid_argument("--xr-scale: must be greater than 0");
  pointFilterFrom(o.render.filter, FilterTarget::Gpu);
  RenderSource source = openRenderSource({.input = o.input, .command = "view"}, o.lod);
  paintScalarColors(source, o.render, false, "view");
  // With a display, the mirror window's GLX context draws (XR_KHR_opengl_enable's Xlib
  // binding); without one, a headless EGL context (XR_MNDX_egl_enable).
  std::unique_ptr<XrMirrorWindow> mirror;
  std::unique_ptr<GlContext> context;
  const char* display = std::getenv("DISPLAY");
  if (!o.no_mirror && display && *display) {
    mirror = std::make_unique<XrMirrorWindow>(o.mirror_width, o.mirror_height,
                                              "Parallax - " + o.input + " (XR mirror)");
    context = GlContext::adoptCurrent();
  } else {
    context = GlContext::createHeadless();
  }
  // The cloud is kept for the laser's picks (exact source values, as `pick` reports them).
  RenderScene scene = uploadRenderSource(source, true);
  std::unique_ptr<PickSource> pick_source = source.lod()
                                                ? std::make_unique<PickSource>(*source.octree)
                                                : std::make_unique<PickSource>(source.cloud);

  const Bounds3& bounds = scene.extent.bounds;
  StagePlacement placement = o.tabletop ? tabletopPlacement(bounds) : StagePlacement{};
  if (!o.tabletop) placement.origin = baseCentre(bounds);
  if (!o.origin.empty()) placement.origin = {o.origin[0], o.origin[1], o.origin[2]};
  if (o.scale > 0) placement.scale = o.scale;

  XrHeadset headset("parallax view");
  Locomotion locomotion(placement);
  // view's --measurements FILE: shown, and the headset's written back to it at the end.
  MeasurementDocument measurements;
  if (!o.measurements_file.empty() && std::filesystem::exists(o.measurements_file)) {
    measurements = loadMeasurementDocument(o.measurements_file);
  }
  std::vector<HeadsetProfileSummary> profiles;  // of the profiles made in the headset
  std::unique_ptr<OverlayFont> plot_font;       // the panels' labels, made with the first panel
  glm::dvec3 head{0.0};                         // file coordinates, this frame's (a panel faces it)
  HeadsetMeasureTool tool(o.profile_width);     // what the trigger measures, and its points so far
  // The profile that is measurement `index`, extracted at once from every point of the source, as
  // the window's is for its panel, and summed up in a label (when it is made, and again when a
  // vertex of it has moved).
  const auto summarizeProfile = [&](std::size_t index) {
    const Measurement& done = measurements.measurements[index];
    try {
      const HeightProfile profile =
          source.lod() ? extractProfile(*source.octree, done.points, done.profile_width)
                       : extractProfile(source.cloud, done.points, done.profile_width);
      const char* from = source.lod() ? "every point of the octree" : "every point of the file";
      std::fprintf(stderr, "parallax view --xr: profile of measurement %zu: %zu points from %s\n",
                   index + 1, profile.samples.size(), from);
      std::string text = std::to_string(profile.samples.size()) + " points";
      if (!profile.samples.empty()) {
        const HeightRange range = heightRange(profile);
        char heights[96];
        std::snprintf(heights, sizeof(heights), ", heights %.2f to %.2f m", range.low, range.high);
        text += heights;
      }
      if (!plot_font) plot_font = std::make_unique<OverlayFont>();
      const std::string title = "profile " + std::to_string(index + 1) + ": " +
                                std::to_string(profile.samples.size()) + " points";
      profiles.push_back({index, done.points.front(), text,
                          profilePanel(profile, done.points, head, title, *plot_font)});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "parallax view --xr: no profile of measurement %zu: %s\n", index + 1,
                   e.what());
    }
  };
  // A finished measurement: printed as the window prints it (six decimals, micrometres in metres:
  // what tests compare) and added to the document.
  const auto finish = [&](const Measurement& done) {
    std::fprintf(stderr, "parallax view --xr: %s\n", describeMeasurement(done, 6).c_str());
    measurements.measurements.push_back(done);
    if (done.kind == MeasurementKind::Profile) {
      summarizeProfile(measurements.measurements.size() - 1);
    }
  };
  // Measurement `index` leaves the document (with its profile's label, and any grab of it).
  const auto erase = [&](std::size_t index) {
    std::vector<Measurement>& list = measurements.measurements;
    std::fprintf(stderr, "parallax view --xr: deleted %s\n",
                 describeMeasurement(list[index], 6).c_str());
    list.erase(list.begin() + std::ptrdiff_t(index));
    std::erase_if(profiles, [&](const HeadsetProfileSummary& p) { return p.measurement == index; });
    for (HeadsetProfileSummary& p : profiles) p.measurement -= p.measurement > index ? 1 : 0;
    tool.erased(index);
  };
  Renderer renderer;
  std::unique_ptr<ComfortVignette> vignette;
  if (o.vignette) vignette = std::make_unique<ComfortVignette>();
  std::optional<RenderSettings> settings;
  // An octree's point budget follows the frame time (a whole cloud is drawn whole).
  FrameBudget frame_budget(
      {.most = o.lod.budget, .least = std::min<std::uint64_t>(100'000, o.lod.budget)});
  LodOptions lod = o.lod;
  std::unique_ptr<RenderTarget> canvas;  // both eyes, each in a viewport taller than its picture
  FrameStats last;
  long long frames_arriving = 0;  // an octree's frames drawn while selected nodes were on their way
  const XrSessionStats stats = headset.run(
      [&](const XrFrameInfo& frame) {
        const auto frame_start = std::chrono::steady_clock::now();
        lod.budget = frame_budget.budget();
        const LocomotionEvents events =
            frame.input ? locomotion.update(*frame.input) : LocomotionEvents{};
        if (frame.input) head = stageToFile(locomotion.placement(), frame.input->head);
        StereoFrame views;
        std::vector<EyeView> eyes;
        int rows = 0;
        const auto placeEyes = [&] {
          views.views.clear();
          eyes.clear();
          rows = 0;
          for (const XrEye& eye : frame.eyes) {
            eyes.push_back(eyeView(locomotion.placement(), eye.fov, eye.pose, eye.viewport.x,
                                   eye.viewport.width, eye.viewport.height));
            views.views.push_back(eyes.back().view);
            rows = std::max(rows, eyes.back().view.viewport.height);
          }
        };
        placeEyes();
        // One draw set (one LOD selection, one node cache) for both eyes, drawn in one pass.
        // What has arrived: a headset's frame never waits for the loading (the runtime would
        // drop it and the user's view would freeze); nodes still on their way come in later
        // frames.
        const DrawSet* draw_set = &arrivedDrawSet(scene, source, views, lod);
        if (scene.lod && !scene.lod->complete()) ++frames_arriving;
        if (!settings) {
          // view's look: what the options leave open, chosen for the cloud as the window does.
          // An octree's first frame may have drawn nothing yet: its sizes follow the octree's
          // spacing, about a level-3 node's as the window's (viewer.cpp), not that frame's.
          const double spacing = source.lod() && source.octree->info().spacing > 0
                                     ? source.octree->info().spacing / 8.0
                                     : draw_set->typical_spacing;
          const RenderSettings asked = renderSettingsFrom(o.render, spacing);
          const LookTraits traits =
              source.lod() ? LookTraits{.spacing_known = source.octree->info().spacing > 0,
                                        .has_normals = source.octree->info().has_normals}
                           : LookTraits{.spacing_known = scene.gpu->typicalSpacing() > 0,
                                        .has_normals = scene.gpu->hasNormals()};
          settings = viewerLook(asked, asked, o.look, traits);
        }
        // The laser's pick of hand h this frame: the front-most point within its cone.
        const auto laserPick = [&](int h) {
          const View laser = laserView(locomotion.placement(), frame.input->hands[h].aim);
          return pickPoint(renderer, *pick_source, *draw_set, std::span(&laser, 1),
                           Composition::Direct, *settings, kLaserPixels, kLaserPixels,
                           {kLaserPixels / 2, kLaserPixels / 2, kLaserPixels / 2, false});
        };
        for (int h = 0; h < 2 && frame.input; ++h) {
          const XrHandInput& hand = frame.input->hands[h];
          if (events.remove[h] && !measurements.measurements.empty()) {
            // The tool button held: the measurement under the laser goes, the last one when the
            // laser is on none.
            const auto under =
                hand.tracked ? measurementUnderLaser(measurements.measurements,
                                                     laserRay(locomotion.placement(), hand.aim))
                             : std::nullopt;
            erase(under.value_or(measurements.measurements.size() - 1));
          }
          if (events.let_go[h]) {
            const bool added = tool.holdsInserted(h);
            if (const auto moved = tool.release(h)) {
              // The vertex stays where the last pick put it; the measurement's value is measure/'s
              // on its new points, as for a fresh pick.
              const Measurement& m = measurements.measurements[moved->measurement];
              const glm::dvec3& at = m.points[moved->vertex];
              std::fprintf(stderr,
                           "parallax view --xr: %s vertex %zu of measurement %zu %s %s,%s,%s: %s\n",
                           added ? "added" : "moved", moved->vertex + 1, moved->measurement + 1,
                           added ? "at" : "to", formatAttributeValue(at.x).c_str(),
                           formatAttributeValue(at.y).c_str(), formatAttributeValue(at.z).c_str(),
                           describeMeasurement(m, 6).c_str());
              if (m.kind == MeasurementKind::Profile) {
                std::erase_if(profiles, [&](const HeadsetProfileSummary& p) {
                  return p.measurement == moved->measurement;
                });
                summarizeProfile(moved->measurement);
              }
            }
          }
          if (events.tool_down[h] && tool.grabbed(h)) {
            // The tool button on a held vertex removes it, at once; the press is nothing else
            // (no next tool at its release, no delete when held).
            locomotion.claimToolPress(h);
            const VertexRemoval removal = *tool.removeHeld(h, measurements.measurements);
            const Measurement& m = measurements.measurements[removal.vertex.measurement];
            const std::string kind(measurementKindName(m.kind));
            if (removal.removed) {
              std::fprintf(stderr,
                           "parallax view --xr: removed vertex %zu of measurement %zu: %s\n",
                           removal.vertex.vertex + 1, removal.vertex.measurement + 1,
                           describeMeasurement(m, 6).c_str());
            } else if (vertexCountIsFree(m.kind)) {
              std::fprintf(stderr,
                           "parallax view --xr: vertex %zu of measurement %zu stays: the %s keeps "
                           "at least %zu points\n",
                           removal.vertex.vertex + 1, removal.vertex.measurement + 1, kind.c_str(),
                           minimumVertices(m.kind));
            } else {
              std::fprintf(stderr,
                           "parallax view --xr: vertex %zu of measurement %zu stays: the headset "
                           "removes vertices of distances and areas only (this is a %s)\n",
                           removal.vertex.vertex + 1, removal.vertex.measurement + 1, kind.c_str());
            }
          }
          bool picks = events.pick[h];
          if (picks) {
            // A press on a vertex grabs it; a press on a distance's or an area's line adds a
            // vertex there and grabs it; only a press on neither picks.
            const LaserRay ray = laserRay(locomotion.placement(), hand.aim);
            if (const auto grabbed = tool.grab(h, measurements.measurements, ray)) {
              std::fprintf(stderr, "parallax view --xr: grabbed vertex %zu of measurement %zu\n",
                           grabbed->vertex + 1, grabbed->measurement + 1);
              picks = false;
            } else if (const auto segment = segmentUnderLaser(measurements.measurements, ray)) {
              // At the laser's point on the cloud, as a drag would put it; on the line itself
              // when the laser hits nothing there.
              const auto hit = laserPick(h);
              const MeasurementVertex added = tool.insert(h, measurements.measurements, *segment,
                                                          hit ? hit->position : segment->closest);
              std::fprintf(stderr,
                           "parallax view --xr: inserted vertex %zu in measurement %zu (%s)\n",
                           added.vertex + 1, added.measurement + 1,
                           hit ? "at the laser's point" : "on its line");
              picks = false;
            }
          } else if (tool.grabbed(h) && !events.let_go[h]) {
            // Held: the vertex follows the laser's pick (no point under it: it stays).
            if (const auto hit = laserPick(h)) {
              tool.drag(h, measurements.measurements, hit->position);
            }
          }
          if (events.tool[h]) {
            if (const auto area = tool.toolButton()) {
              finish(*area);
            } else {
              std::fprintf(stderr, "parallax view --xr: tool %s\n",
                           std::string(measurementKindName(tool.kind())).c_str());
            }
          }
          if (!picks && !events.teleport[h]) continue;
          const auto hit = laserPick(h);
          if (!hit) continue;
          std::fprintf(stderr, "parallax view --xr: laser pick %s,%s,%s\n",
                       formatAttributeValue(hit->position.x).c_str(),
                       formatAttributeValue(hit->position.y).c_str(),
                       formatAttributeValue(hit->position.z).c_str());
          if (events.teleport[h]) {
            locomotion.teleportTo(hit->position, frame.input->head);
            placeEyes();
            draw_set = &arrivedDrawSet(scene, source, views, lod);
            continue;
          }
          if (picks) {
            if (const auto done = tool.pick(hit->position)) finish(*done);
          }
        }
        renderer.setOverlay(
            laserOverlay(locomotion.placement(), frame.input, measurements, tool, profiles));
        if (!canvas || canvas->width() != frame.width || canvas->height() != rows) {
          canvas = std::make_unique<RenderTarget>(frame.width, rows);
        }
        last =
            renderer.render(*draw_set, views, *settings, canvas->framebuffer(), frame.width, rows);
        for (std::size_t v = 0; v < eyes.size(); ++v) {
          const Viewport& to = frame.eyes[v].viewport;
          const int from_y = eyes[v].source_y;
          glBlitNamedFramebuffer(canvas->framebuffer(), frame.framebuffer, to.x, from_y,
                                 to.x + to.width, from_y + to.height, to.x, to.y, to.x + to.width,
                                 to.y + to.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
        if (vignette && locomotion.flying()) {
          for (const XrEye& eye : frame.eyes)
            vignette->draw(frame.framebuffer, eye.viewport, eye.fov);
        }
        if (mirror && !mirror->show(frame.framebuffer, frame.eyes[0].viewport)) {
          headset.requestExit();
        }
        if (scene.lod && frame.input) {
          glFinish();  // the frame's whole cost, as the runtime will wait for it
          const std::chrono::duration<double> took = std::chrono::steady_clock::now() - frame_start;
          frame_budget.update(took.count(), frame.input->period_s, last.points_drawn);
        }
      },
      o.frames);
  if (!o.measurements_file.empty()) {
    // The document as the window saves it (its camera, if the file had one, kept: a headset's
    // eyes are no window's camera).
    saveMeasurementDocument(measurements, o.measurements_file);
    std::fprintf(stderr, "parallax view --xr: %zu measurements saved to %s\n",
                 measurements.measurements.size(), o.measurements_file.c_str());
  }
  // The placement as the controllers left it, to the last digit (tests compare it).
  const StagePlacement& end = locomotion.placement();
  std::fprintf(
      stderr,
      "parallax view --xr: %s on %s through %s, %lld frames of 2 x %dx%d drawn (%llu points, "
      "rasterizer %s, budget %llu, %lld while nodes were arriving), origin %.17g,%.17g,%.17g, "
      "scale %.17g, yaw %.17g\n",
      stats.system.c_str(), stats.runtime.c_str(), stats.binding.c_str(), stats.frames_drawn,
      stats.eye_width, stats.eye_height, static_cast<unsigned long long>(last.points_drawn),
      last.rasterizer == RasterizerKind::Compute ? "compute" : "points",
      static_cast<unsigned long long>(scene.lod ? frame_budget.budget() : scene.points),
      frames_arriving, end.origin.x, end.origin.y, end.origin.z, end.scale, end.yaw);
  return 0;
}

}  // namespace parallax::cli
