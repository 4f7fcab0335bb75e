// The registration preview's state in a viewer session (internal to src/viewer;
// registration_panel.cpp): the target cloud, the ICP run on its own thread, both clouds coloured
// apart before and after the transform it found, and where an accepted transform is written.
#pragma once

#include <array>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "registration/point_pairs.h"
#include "registration/point_to_plane_icp.h"
#include "render/draw_set.h"
#include "render/point_buffers.h"

namespace parallax::viewer_internal {

// What a run gives back: both clouds it registered and its result.
struct RegistrationRun {
  std::shared_ptr<const PointCloud> source, target;
  IcpResult result;
};

// Point-pairs picking (registration_pairs.cpp; CloudCompare's "align (point pairs picking)"):
// clicks alternate between a point of the source and its match on the target; from three
// pairs on, the rigid transform they give (registration/point_pairs.h) moves the source in the
// preview at once, and ICP ("refine") starts from it.
struct PairPicking {
  bool active = false;
  // The target file read on a thread of its own (the picking starts once it is here).
  std::future<std::shared_ptr<const PointCloud>> target_load;
  std::shared_ptr<const PointCloud> source, target;  // world coordinates as the files hold them
  std::filesystem::path target_path;                 // what `target` was read from
  // Picked points, world coordinates as the files hold them: source[i] and target[i] are pair
  // i + 1; source may hold one more (a pair waiting for its target point).
  std::vector<std::array<double, 3>> source_points, target_points;
  std::optional<PairFit> fit;  // from three complete pairs on
  std::string fit_error;       // why the pairs give no transform (collinear source points)
  // Each side drawn apart (the source moved by the fit, or not at all before three pairs), so that
  // a click is picked on the side it is for.
  std::unique_ptr<GpuPointCloud> source_layer, target_layer;
  DrawSet shown_set;  // both layers, as drawn
};

struct RegistrationSession {
  std::array<char, 1024> target_text{};  // the panel's target field
  std::array<char, 1024> output_text{};  // where Accept writes the transform
  double max_distance = 0.0;             // ICP's (0: its default)
  // The run under way (valid() while it is), on a copy of the cloud shown.
  std::future<RegistrationRun> run;
  std::shared_ptr<const PointCloud> source, target;  // what the last run registered
  std::optional<IcpResult> result;
  // The previews on the GPU (the target, the source before and after the transform; each drawn
  // with the target), and which is shown; `shown` false: the cloud as it is.
  std::unique_ptr<GpuPointCloud> target_layer, before, after;
  DrawSet before_set, after_set;
  bool shown = false, show_after = true;
  std::string message;           // the last outcome, or why it could not start
  bool start_requested = false;  // --register-with: start once the cloud is shown
  bool pairs_requested = false;  // --pick-pairs: start picking pairs once the cloud is shown
  PairPicking pairs;
};

}  // namespace parallax::viewer_internal
