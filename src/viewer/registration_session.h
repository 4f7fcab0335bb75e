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

#include "core/point_cloud.h"
#include "registration/point_to_plane_icp.h"
#include "render/draw_set.h"
#include "render/point_buffers.h"

namespace parallax::viewer_internal {

// What a run gives back: both clouds it registered and its result.
struct RegistrationRun {
  std::shared_ptr<const PointCloud> source, target;
  IcpResult result;
};

struct RegistrationSession {
  std::array<char, 1024> target_text{};  // the panel's target field
  std::array<char, 1024> output_text{};  // where Accept writes the transform
  double max_distance = 0.0;             // ICP's (0: its default)
  // The run under way (valid() while it is), on a copy of the cloud shown.
  std::future<RegistrationRun> run;
  std::shared_ptr<const PointCloud> source, target;  // what the last run registered
  std::optional<IcpResult> result;
  // The two previews on the GPU (the source before and after the transform, the target with
  // each), and which is shown; `shown` false: the cloud as it is.
  std::unique_ptr<GpuPointCloud> before, after;
  DrawSet before_set, after_set;
  bool shown = false, show_after = true;
  std::string message;           // the last outcome, or why it could not start
  bool start_requested = false;  // --register-with: start once the cloud is shown
};

}  // namespace parallax::viewer_internal
