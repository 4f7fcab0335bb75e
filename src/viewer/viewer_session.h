// The viewer's state and the pieces of it in other files (viewer_panel.cpp: the on-screen panel
// and the help window); internal to src/viewer.
#pragma once

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lod/background_octree_build.h"
#include "lod/large_file.h"
#include "lod/octree.h"
#include "lod/octree_cache.h"
#include "render/camera.h"
#include "render/frame_times.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/point_picker.h"
#include "render/progressive.h"
#include "render/renderer.h"
#include "viewer/camera_controller.h"
#include "viewer/measure_session.h"
#include "viewer/process_session.h"
#include "viewer/registration_session.h"
#include "viewer/viewer.h"

namespace parallax::viewer_internal {

// State shared with the GLFW callbacks (through the window's user pointer).
struct Session {
  const ViewerOptions* options = nullptr;
  GLFWwindow* window = nullptr;
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<GpuPointCloud> cloud;  // a whole file, or the preview of a large one
  DrawSet draw_set;                      // all of `cloud`'s chunks
  // The points `cloud` was uploaded from: picking reads the picked point back from them (the GPU
  // holds chunk-relative floats, not the file's values).
  std::unique_ptr<PointCloud> cloud_points;
  // A whole file shown with fewer attributes than it holds (cloud_attributes.cpp): the file and
  // every attribute it holds; the others are read into `cloud_points` when first asked for.
  // Empty path: `cloud_points` holds all its source has (a preview, a processing result, ...).
  std::filesystem::path cloud_file;
  std::vector<std::string> cloud_file_attributes;
  // The scalar colouring `cloud`'s colours show (settings.scalar when it was uploaded), the range
  // it used (the attribute's own when none was asked), and why the asked one could not be shown.
  ScalarColoring shown_scalar;
  ScalarRange shown_scalar_range;
  std::string scalar_error;
  bool show_legend = true;  // the scalar colouring's legend over the picture (legend_overlay.cpp)
  // A raster drawn with what is shown (raster_panel.cpp): its points on the GPU, the file, the
  // ramp it was coloured with and the one the panel asks for, the panel's path field.
  std::unique_ptr<GpuPointCloud> raster_layer;
  std::uint64_t raster_layer_cells = 0;
  std::filesystem::path raster_path;
  ColorRamp raster_ramp = ColorRamp::Viridis, raster_shown_ramp = ColorRamp::Viridis;
  std::array<char, 1024> raster_path_text{};
  std::string raster_error;
  // Level of detail: the octree (and the temporary folder holding it, with --no-cache) and the
  // scene streaming it; declared in this order so that they end in the reverse one.
  std::unique_ptr<OctreeLocation> lod_location;
  std::unique_ptr<Octree> octree;
  std::unique_ptr<LodScene> lod;
  // While the octree's nodes are read again for a new look (octree_attributes.cpp): the scene
  // before, no longer loading, whose last picture is drawn with the look it was loaded for until
  // `lod` draws as many points (or all it selected), so that no frame is blank or miscoloured.
  struct PreviousLod {
    std::unique_ptr<LodScene> scene;
    RenderSettings settings;  // the look its last picture was drawn with
    std::uint64_t points = 0;
  };
  std::optional<PreviousLod> previous_lod;
  // The attributes the octree holds (every one, as it opened) and those its nodes are read with
  // now (Octree::selectAttributes; info().attributes): what the look drawn needs of them.
  std::vector<std::string> octree_attributes, octree_read;
  LodFrameSettings lod_settings;
  LodStats lod_stats;
  // The octree of a large file being built; `cloud` shows its preview meanwhile.
  std::unique_ptr<BackgroundOctreeBuild> build;
  // The next build, started once the preview is on screen (the build takes every core it gets).
  std::unique_ptr<OctreeLocation> build_pending;
  // An octree URL being opened (viewer.cpp: startOpeningUrl), shown once there.
  struct OpeningUrl {
    std::string url;
    bool first = false;
    std::future<std::unique_ptr<Octree>> octree;
  };
  std::optional<OpeningUrl> opening;
  bool build_keeps_camera = false;  // the preview placed the camera
  bool build_first = false;         // the file given on the command line (its camera options)
  bool first_picture_reported = false;
  // Progressive refinement of octree frames (frame_budget_ms 0: off). `picture_parts`: the frames
  // that drew the picture now shown (1 unless refined); reported once for the first picture that
  // needed several.
  ProgressiveRefinement progressive;
  double frame_budget_ms = 0;
  int picture_parts = 0;
  bool refined_picture_reported = false;
  // The picture shown, for the panel's headline: the points in it (every part of a refined
  // picture) and the seconds from the start of its first part to the end of its last.
  std::uint64_t picture_points = 0;
  double picture_seconds = 0;
  std::chrono::steady_clock::time_point picture_start;
  // The frames of a moving camera (start of one frame to the start of the next, everything
  // included: what the user feels), summarised in the panel as `bench render --orbit` does.
  FrameTimes moving_frames;
  bool moved_last_frame = false;
  RenderSettings settings;
  StereoSettings stereo;
  bool quad_buffer = false;  // the window has left and right back buffers
  Camera camera;
  ViewExtent extent;  // what is shown, for fitting the camera (F)
  CameraController controller;
  std::string loaded_name;
  std::filesystem::path
      shown_path;      // the file (or octree, URL) shown, as opened: what is processed
  std::string status;  // last message for the user: errors, screenshot paths
  // The last open that failed (empty once a cloud opens): shown at the top of the panel and,
  // while nothing is shown, in the middle of the window.
  std::string error;
  bool show_help = false, show_panel = true, vsync = true;
  bool close_popups = false;  // Esc with a list of the panel open: the next frame closes it
  // The panel's right edge in window pixels while it is shown and expanded (0 when collapsed):
  // the first view and F frame the cloud in the part of the window right of it.
  std::optional<float> panel_right;  // nullopt: not drawn yet (its default place is assumed)
  bool screenshot_requested = false;
  bool screenshot_with_panel = false;  // Shift + P: the window as seen, panel included
  int screenshot_count = 0;
  // PARALLAX_VIEW_TRACE_KEYS=1: each key pressed is logged once the frame that handled it has
  // been drawn, so that a driver (the window tests) waits on the viewer, never for a fixed time.
  bool trace_keys = false;
  std::vector<int> keys_this_frame;
  double scroll_steps = 0;
  std::vector<std::string> dropped;
  double last_click_time = -1;
  bool pick_requested = false;        // double-click: a new pivot
  bool point_pick_requested = false;  // Ctrl + click: the point and its attributes
  std::optional<PickResult> picked;   // shown in the panel's "Picked point" section
  // What picked points are read from, made for the scene shown (`pick_scene`), so that its last
  // octree nodes read stay cached between clicks.
  std::unique_ptr<PickSource> pick_source;
  const void* pick_scene = nullptr;
  // What the last drawn picture shows: points are drawn again only when one of these changes
  // (on llvmpipe a large cloud takes a good part of a second), otherwise the picture is reused.
  struct Drawn {
    const void* scene = nullptr;  // the GpuPointCloud or the LodScene
    std::uint64_t budget = 0;
    double min_node_size = 0;
    Camera camera;
    RenderSettings settings;
    StereoSettings stereo;
    int width = 0, height = 0;
    friend bool operator==(const Drawn&, const Drawn&) = default;
  };
  std::optional<Drawn> drawn;
  // The filter panel's state (filter_panel.cpp); settings.filter is what is drawn.
  struct FilterEditor {
    std::array<std::uint32_t, 8> listed{};  // bit c: class c has a checkbox
    bool classified = false;                // false: no classification, every point is class 0
    bool box_enabled = false, box_outside = false;
    bool highlight = false;  // tint the region's content instead (box_outside unused)
    ClipBox box;             // world coordinates; applied to settings.filter while enabled
    // Returns: kinds (first, last, intermediate, single, multiple) and return numbers (bit r),
    // applied while enabled; ranges applied while enabled, their sliders over the data's range.
    bool returns_enabled = false;
    std::array<bool, 5> return_kinds{};
    std::uint32_t return_numbers = 0;
    struct Range {
      bool enabled = false;
      ValueRange data, value;
    };
    Range intensity, elevation, gps_time;
    bool polygon_enabled = false;
    std::vector<std::array<double, 2>> polygon;  // the command line's --clip-polygon
  };
  FilterEditor filter_editor;
  // Measurements and annotations (measure_tool.cpp, measure_panel.cpp).
  MeasureSession measure;
  // The Processing panel (process_panel.cpp); last, so that a run under way ends (is waited for)
  // first when the session ends.
  ProcessSession process;
  RegistrationSession registration;  // registration_panel.cpp
};

// The session of a window (its user pointer).
Session& sessionOf(GLFWwindow* window);
// GLFW callbacks (viewer_input.cpp); installed before ImGui's backend, which chains to them.
void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
void onScroll(GLFWwindow* window, double x, double y);
void onMouseButton(GLFWwindow* window, int button, int action, int mods);
void onDrop(GLFWwindow* window, int count, const char** paths);
// The buttons and keys held now, less those ImGui takes (a field being edited, the panel hovered).
InputState readInput(GLFWwindow* window);

// Fits the camera to what is shown (F).
void fitCamera(Session& s);
// Quad-buffer only where the window has a stereo visual; elsewhere sbs, and the user is told.
void setStereoMode(Session& s, StereoMode mode);
// Who draws points (R cycles auto, compute, points); the user is told, with the reason where
// the compute rasterizer cannot draw the frame.
void setRasterizer(Session& s, RasterizerKind kind);

// The panel (G): file, frame time, level of detail, every render setting, stereo, camera,
// filters.
void drawPanel(Session& s, const FrameStats& stats);
// The panel's width before it is first drawn (then what it was drawn with): wide enough for
// every label beside its field.
float panelWidth();
// In the stereo modes that show each eye in its own half of the window (sbs, sbs-squeezed, tb)
// the panel starts collapsed to its title bar: over one eye and not the other it would cover
// most of that eye and break the fusion. A click on its title bar opens it.
bool panelStartsCollapsed(const Session& s);
// While nothing is shown: what to do (drop a file) and why the last open failed, in the middle
// of the window where the eye is.
void drawEmptyWindowMessage(const Session& s);
// While a cloud is shown and the panel is hidden or collapsed: the last failure to open and the
// Volume tool's error (volumeError), at the top of the window (the panel shows them at its top
// otherwise).
void drawErrorBanner(const Session& s);
// The filter part of the panel: a checkbox per class, the clip box editor.
void drawFilterPanel(Session& s);
// Prepares the filter panel for a newly opened cloud (s.extent set): the classes it may have
// (those of `points` when they are the whole cloud, else ASPRS's named classes and those seen in
// `points`, a preview or nothing) and a clip box over its bounds, or the command line's box for
// the first cloud. Classes unchecked earlier stay unchecked.
void prepareFilters(Session& s, const PointCloud* points, bool whole, bool has_classification,
                    bool first);
// The clip box's twelve edges, turned as it is, while its editor is on and the panel shown.
void appendClipBoxOutline(const Session& s, OverlayScene& scene);
// The keys and mouse (H).
void drawHelp();
// Reads the raster at `path` as the layer drawn with the cloud (raster_panel.cpp); false, with
// raster_error and a line on stderr, where it cannot be read.
bool loadRasterLayer(Session& s, const std::filesystem::path& path);
// The panel's Raster layer section: path, ramp, Load, Remove.
void drawRasterPanel(Session& s);

// The registration preview (registration_panel.cpp). prepareRegistration sets the target and
// transform file the command line gave and, with a target, asks for a run once the cloud is
// shown; startRegistration runs ICP of the cloud shown onto the target on a thread of its own;
// updateRegistration, once a frame, starts an asked run and takes a finished one's result;
// registrationDrawSet is the preview to draw in place of the cloud (nullptr: the cloud);
// acceptRegistration writes the transform found (false, with the reason in the panel, where
// there is none or it cannot be written).
// `init`: where ICP starts (the point pairs' transform for a refine; the identity otherwise).
// With `pick_pairs`, the command line's target starts point-pairs picking instead of ICP.
void prepareRegistration(Session& s, const std::filesystem::path& target,
                         const std::filesystem::path& output, bool pick_pairs);
void startRegistration(Session& s, const RigidTransform& init = {});
void updateRegistration(Session& s);
const DrawSet* registrationDrawSet(const Session& s);
bool acceptRegistration(Session& s);
void drawRegistrationPanel(Session& s);

// Point-pairs picking (registration_pairs.cpp). startPairPicking reads the target of the panel's
// field on a thread of its own; updatePairPicking, once a frame, starts what --pick-pairs asked
// and, once the target is read, shows both clouds coloured apart and takes clicks:
// pairPickingClick picks the next point (the source's, then its match on the target) at window
// pixel (x, y) (bottom-left origin) and fits the transform from three pairs on; removePair and
// removeLastPick take picks back; refinePairs runs ICP from the fit (startRegistration);
// registrationKey handles Ctrl + T (Accept) and, while picking, Enter (refine) and Backspace
// (undo) (true: taken);
// appendPairOverlay marks and numbers the picks (S1, T1, ...) on both clouds.
// Prints a transform's three rows on one line of stderr, in full precision ("parallax view:
// WHAT: m00 m01 ... m23"), for scripts and tests.
void logRegistrationTransform(const char* what, const RigidTransform& transform);
void startPairPicking(Session& s);
void stopPairPicking(Session& s);
void updatePairPicking(Session& s);
bool pairPickingTakesClicks(const Session& s);
const DrawSet* pairPickingDrawSet(const Session& s);
void pairPickingClick(Session& s, int x, int y, int width, int height);
void removePair(Session& s, std::size_t index);
void removeLastPick(Session& s);
void refinePairs(Session& s);
bool registrationKey(Session& s, int key, int mods);
void appendPairOverlay(const Session& s, OverlayScene& scene);
// The panel's part for the pairs: start, the next side, the pairs with their residuals and a
// remove button each, the fit and Refine.
void drawPairPickingPanel(Session& s);
// The legend of the scalar colouring shown (legend_overlay.cpp), at the window's right edge,
// while show_legend and an attribute colours the cloud.
void drawScalarLegendOverlay(Session& s);

// The point under window pixel (x, y) (bottom-left origin) of the frame shown, read back from
// the source with every attribute; std::nullopt (and the user told) where there is none or the
// source cannot be read again.
std::optional<PickResult> pickAt(Session& s, int x, int y, int width, int height);

// Measurement tools (measure_tool.cpp). A picked point for the active tool: a vertex of the
// measurement being drawn (point, height and angle finish themselves) or a new annotation.
void measureClick(Session& s, const PickResult& picked);
void setMeasureTool(Session& s, MeasureTool tool);
// Adds the measurement being drawn to the document when it has enough points; prints it on
// stderr ("parallax view: distance 12.345678 m (2 points)").
void finishMeasurement(Session& s);
// Cancels the measurement being drawn; an edit puts the measurement back as it was.
void cancelMeasurement(Session& s);
void removeLastMeasurePoint(Session& s);
// Removes vertex `index` of the measurement being drawn or edited.
void removeMeasurePoint(Session& s, std::size_t index);
// Reopens the selected measurement: its points become the ones being drawn (more can be clicked,
// any removed), Enter puts it back in its place, Escape restores it.
void editSelectedMeasurement(Session& s);
void deleteSelectedMeasurement(Session& s);
// Enter (finish), Escape (cancel, while drawing), Backspace (remove the last point), Delete (the
// selected measurement), Ctrl + E (edit the selected measurement), Ctrl + S (save the measurement
// file), Ctrl + X (export the selected profile: CSV, with Shift LAS): true when the key was the
// tools'.
bool measureKey(Session& s, int key, int mods);
// Animates the camera to the annotation's saved camera, or looks at its point from here.
void flyToAnnotation(Session& s, const Annotation& annotation);
// Moves the camera along a flight; true while one is under way.
bool updateMeasureFlight(Session& s);
// Uploads `cloud_points` as `cloud`, coloured by settings.scalar where it names an attribute the
// cloud has (otherwise scalar_error says why, and the cloud's own colours are uploaded).
void uploadShownCloud(Session& s);

// The octree's nodes read with what the look needs (octree_attributes.cpp). startLodScene makes
// s.lod for s.octree just opened (every attribute selected, the look chosen): its nodes are read
// with the attributes the look draws (render_settings.h attributesDrawn). Once a frame,
// updateLodAttributes reads them again when the look (colour mode, lighting, filters) needs an
// attribute the octree holds and they were read without: the scene shown stops loading and is
// kept as s.previous_lod, and a new scene loads with what the look needs now.
void startLodScene(Session& s);
void updateLodAttributes(Session& s);
// While a previous scene is kept: its picture and, in `look`, the look to draw it with; nullptr
// once the new scene draws as many points or all it selected (the previous one is then dropped
// and `changed` set: the picture starts again).
const DrawSet* previousLodPicture(Session& s, const RenderSettings*& look, bool& changed);

// A file drawn whole, read with what the first picture needs (cloud_attributes.cpp).
// openCloudFile reads it (the look on the command line, colour or else intensity,
// classification, normals) and shows it; once a frame, updateCloudAttributes reads into the
// cloud what the look now needs (colour mode, scalar field, lighting, filters) and the file
// holds, and uploads it again; completeCloud reads every attribute (picking, profiles);
// cloudScalarFields lists the file's scalar attributes, read or not, for the panel.
void openCloudFile(Session& s, const std::filesystem::path& path, bool first);
void updateCloudAttributes(Session& s);
void completeCloud(Session& s);
std::vector<std::string> cloudScalarFields(const Session& s);
// The filter panel's intensity and GPS-time sliders over the data's range once the cloud has
// the column (read after the cloud opened); ranges the user set are kept.
void updateFilterRanges(Session& s);

// Opens a file, an octree or a URL as what is shown (viewer.cpp): `first` for the command line's
// (its camera options). Failures are reported in the panel and on stderr.
void openFile(Session& s, const std::filesystem::path& path, bool first);
// Shows a whole cloud (or a large file's preview: `whole` false) in place of what was shown.
void showCloud(Session& s, PointCloud cloud_points, bool whole, bool place_camera, bool first);

// Processing (process_panel.cpp). startProcessing runs the panel's steps on the file shown (or
// its clip box) on a thread of its own; updateProcessing, once a frame, starts a run the K key
// asked for and shows a finished run's result in place of the input, the camera kept.
void startProcessing(Session& s);
void updateProcessing(Session& s);
// The panel's Processing section: the steps, the output file, Run and the progress bar.
void drawProcessPanel(Session& s);

// Gives the renderer the overlay: the document, the measurement being drawn and, while the panel
// shows its editor, the clip box's outline.
void updateOverlay(Session& s);
// The selected profile measurement's profile, extracted from what is open (cached); nullptr when
// the selection is not a profile.
const MeasureSession::Profile* selectedProfile(Session& s);
// Writes the selected profile into the screenshot folder as profile-N.csv or .las.
void exportProfile(Session& s, bool las);
// Save / Load of s.measure.file (the current camera saved with the measurements).
void saveMeasurements(Session& s);
void loadMeasurements(Session& s);
// The Volume tool (volume_tool.cpp): cut, fill and net volume inside the selected area
// measurement, over the file shown (raster/volume.h, as `parallax volume`), printed on stderr
// ("parallax view: volume of measurement N: cut C fill F net N ...") and shown in the panel's
// Volume part, drawn under the selected area.
void computeSelectedVolume(Session& s);
void drawVolumePanel(Session& s);
// Why the selected area's volume could not be computed (its last try, the area unchanged since);
// nullptr when it was, or was not tried. Shown in the Volume part, at the panel's top and, with
// the panel hidden, over the picture.
const std::string* volumeError(const Session& s);
// `text` wrapped, in the colour of errors (viewer_panel.cpp).
void drawErrorText(const std::string& text);
// The panel's Measure section (measure_panel.cpp).
void drawMeasurePanel(Session& s);

}  // namespace parallax::viewer_internal
