// The measurement state of a viewer session (internal to src/viewer): the document being edited,
// the measurement being drawn, the selection, a computed height profile, a camera flight.
#pragma once

#include <optional>
#include <string>

#include "measure/height_profile.h"
#include "measure/measurement_document.h"
#include "raster/volume.h"
#include "render/camera_path.h"
#include "viewer/measure_tool.h"

namespace parallax::viewer_internal {

struct MeasureSession {
  MeasureTool tool = MeasureTool::None;
  MeasurementDocument document;
  // The measurement being clicked (its kind is the tool's); empty points: none in progress.
  Measurement current;
  std::optional<std::size_t> selected;  // in document.measurements
  // While a measurement of the document is reopened for editing (its points are `current`): its
  // index, and the measurement as it was, which Escape puts back.
  std::optional<std::size_t> editing;
  Measurement editing_original;
  double profile_width = 1.0;     // the next profile's corridor width, world units
  std::string annotation_label;   // the next annotation's label (empty: "Annotation N")
  bool annotation_camera = true;  // save the current camera with new annotations
  std::string file;               // Save / Load (the panel's field)

  // The height profile of one measurement, computed when it is selected (kept until another).
  struct Profile {
    std::size_t measurement = 0;
    Measurement of;  // the measurement it was computed for (recomputed when edited)
    HeightProfile profile;
    std::string source;  // "the whole cloud", "the preview (a sample)", "the octree"
    std::string error;
  };
  std::optional<Profile> profile;

  // The volume inside the selected area measurement (volume_tool.cpp): the surface's cell size
  // and the base asked for (with VolumeBase::Raster, the raster's path as typed in the panel:
  // a DTM, an earlier epoch), and the last result, for the measurement it was computed for.
  double volume_resolution = 0.5;
  VolumeBase volume_base = VolumeBase::Plane;
  std::string volume_base_file;
  struct Volume {
    std::size_t measurement = 0;
    Measurement of;
    VolumeReport report;
    std::string error;
  };
  std::optional<Volume> volume;

  // A flight to an annotation: the camera follows `path` from `start` (glfwGetTime seconds).
  std::optional<CameraPath> flight;
  double flight_start = 0;

  // A left click with a tool active, waiting for the frame to be drawn (window pixels, top-down).
  bool press_valid = false;
  double press_x = 0, press_y = 0;
  bool click_requested = false;
  double click_x = 0, click_y = 0;
};

}  // namespace parallax::viewer_internal
