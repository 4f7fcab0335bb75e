// The panel's Processing section (issue 26 item 6): `parallax process` steps (normals, outliers,
// subsampling, distances; process/process_runner.h, used as it is) run on the file shown, or on
// the points of its clip box, on a thread of their own while the window answers, with a progress
// bar; the result is written to the output file typed (the save) and shown in place of the input,
// the camera kept: lit where the steps added normals (the look the viewer chooses for any cloud
// with normals), coloured by `distance` through the scalar ramp where a step added it.
//
// The runner reads the file again rather than the points on the GPU: it works out of core on the
// file's own values (a float chunk would lose precision), and the output keeps every attribute.
// A run is cancelled by its Cancel button (ProcessOptions::cancel, checked at every tile): its
// temporary output and work files are removed, the input stays shown, the panel says so.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/progress.h"
#include "io/point_file.h"
#include "lod/large_file.h"
#include "process/process_steps.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {
namespace {

// A stage of the run, as the panel's progress bar shows it.
class PanelProgress final : public Progress {
 public:
  PanelProgress(std::shared_ptr<ProcessProgress> shared, std::string stage, std::uint64_t total)
      : shared_(std::move(shared)) {
    {
      const std::lock_guard lock(shared_->mutex);
      shared_->stage = std::move(stage);
    }
    shared_->done = 0;
    shared_->total = total;
  }
  void advance(std::uint64_t amount) override {
    shared_->done += amount;
    if (shared_->hold_first_report && !shared_->held.exchange(true)) {
      std::fprintf(stderr,
                   "parallax view: processing held at its first progress report until Cancel "
                   "(PARALLAX_VIEW_TEST_HOLD_PROCESS)\n");
      shared_->cancel.wait(false);
    }
  }

 private:
  std::shared_ptr<ProcessProgress> shared_;
};

// Beside the screenshots: "NAME-processed.ply" for the file shown.
std::filesystem::path defaultOutput(const Session& s) {
  const std::string stem = s.shown_path.stem().string();
  return s.options->screenshot_dir / ((stem.empty() ? "cloud" : stem) + "-processed.ply");
}

void report(Session& s, std::string message) {
  s.process.message = std::move(message);
  s.status = s.process.message;
  std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
}

// The result in place of the input, the camera kept.
void showResult(Session& s, const std::filesystem::path& path, bool distance) {
  if (distance) {
    // Coloured by the distance through the ramp, over its own range.
    s.settings.scalar.field = "distance";
    s.settings.scalar.range.reset();
    s.settings.color = ColorMode::Rgb;
  }
  if (pointsOverBudget(path, s.lod_settings.selection.point_budget)) {
    openFile(s, path, false);  // its octree, as any large file
  } else {
    showCloud(s, readPointFile(path), true, false, false);
    s.shown_path = path;
  }
}

// For a window test (PARALLAX_VIEW_TRACE_KEYS): where the Cancel button just drawn is, once a
// run, when the panel shows it whole (scrolled to it otherwise).
void traceCancelButton(Session& s) {
  if (s.process.cancel_button_logged) return;
  const ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
  const ImVec2 window_min = ImGui::GetWindowPos();
  const ImVec2 window_max(window_min.x + ImGui::GetWindowSize().x,
                          window_min.y + ImGui::GetWindowSize().y);
  if (min.y < window_min.y || max.y > window_max.y) {
    ImGui::SetScrollHereY(0.5f);
    return;
  }
  s.process.cancel_button_logged = true;
  std::fprintf(stderr, "parallax view: Cancel button at %d %d\n", int((min.x + max.x) / 2),
               int((min.y + max.y) / 2));
}

}  // namespace

void startProcessing(Session& s) {
  ProcessSession& p = s.process;
  p.run_requested = false;
  if (p.run.valid()) {
    report(s, "processing: a run is under way");
    return;
  }
  try {
    if (s.shown_path.empty()) throw std::invalid_argument("open a point file first");
    ProcessOptions options;
    for (const std::string& line : p.steps) options.steps.push_back(parseProcessStep(line));
    if (options.steps.empty()) {
      throw std::invalid_argument(
          "no step (add one: normals 16, outliers statistical:8,2, subsample voxel:0.1, "
          "distance-to FILE)");
    }
    ConvertInput input{s.shown_path, {}, {}};
    const bool clipped = p.clip_box_only && s.filter_editor.box_enabled;
    if (clipped) {
      const ClipBox& box = s.filter_editor.box;
      input.filter.setClipBox(box.box, s.filter_editor.box_outside, box.yaw_degrees);
    }
    options.inputs.push_back(std::move(input));
    options.output = p.output.empty() ? defaultOutput(s) : std::filesystem::path(p.output);
    auto progress = std::make_shared<ProcessProgress>();
    progress->hold_first_report = p.hold_first_report;
    p.cancel_button_logged = false;
    options.progress = [progress](const std::string& stage, std::uint64_t total) {
      return std::unique_ptr<Progress>(std::make_unique<PanelProgress>(progress, stage, total));
    };
    options.cancel = &progress->cancel;  // the factory above keeps `progress` alive
    p.progress = progress;
    p.running_output = options.output;
    p.running_steps = options.steps;
    p.started = std::chrono::steady_clock::now();
    std::string steps;
    for (const ProcessStep& step : options.steps) {
      steps += ' ';  // (appended: GCC 12's -Wrestrict misreads "text" + string, bug 105329)
      steps += describeStep(step);
    }
    std::string message = "processing ";
    message += s.shown_path.string();
    if (clipped) message += " (its clip box)";
    message += " into ";
    message += options.output.string();
    message += ':';
    message += steps;
    report(s, std::move(message));
    p.run = std::async(std::launch::async,
                       [options = std::move(options)] { return runProcess(options); });
  } catch (const std::exception& e) {
    report(s, std::string("cannot process: ") + e.what());
  }
}

void updateProcessing(Session& s) {
  ProcessSession& p = s.process;
  if (p.run_requested) startProcessing(s);
  if (!p.run.valid() || p.run.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - p.started).count();
  try {
    const ProcessReport result = p.run.get();
    bool distance = false;
    for (const ProcessStep& step : p.running_steps) {
      distance = distance || std::holds_alternative<DistanceStep>(step);
    }
    showResult(s, p.running_output, distance);
    char text[96];
    std::snprintf(text, sizeof text, " in %.2f s (%llu points in, %llu out)", seconds,
                  static_cast<unsigned long long>(result.input_points),
                  static_cast<unsigned long long>(result.output_points));
    std::string message = "processed into ";
    message += p.running_output.string();
    message += text;
    report(s, std::move(message));
  } catch (const ProcessCancelled&) {
    report(s, "processing cancelled: nothing written to " + p.running_output.string());
  } catch (const std::exception& e) {
    report(s, std::string("processing failed: ") + e.what());
  }
  p.progress.reset();
}

void drawProcessPanel(Session& s) {
  ProcessSession& p = s.process;
  ImGui::Separator();
  ImGui::TextDisabled("Processing");
  int remove = -1;
  for (std::size_t i = 0; i < p.steps.size(); ++i) {
    ImGui::PushID(int(i));
    ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - 60.0f);
    ImGui::InputText("##step", &p.steps[i]);
    ImGui::SameLine();
    if (ImGui::Button("remove")) remove = int(i);
    try {
      (void)parseProcessStep(p.steps[i]);
    } catch (const std::exception& e) {  // said as it is typed, not only when run
      ImGui::TextWrapped("%s", e.what());
    }
    ImGui::PopID();
  }
  if (remove >= 0) p.steps.erase(p.steps.begin() + remove);
  ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - 60.0f);
  ImGui::InputText("##new step", &p.new_step);
  ImGui::SameLine();
  if (ImGui::Button("add")) p.steps.push_back(p.new_step);
  ImGui::TextDisabled(
      "normals K, outliers statistical:K,S, subsample voxel:SIZE, distance-to FILE, "
      "ground smrf|pmf|csf, height-above-ground");
  if (s.filter_editor.box_enabled) ImGui::Checkbox("clip box only", &p.clip_box_only);
  ImGui::InputTextWithHint("output", defaultOutput(s).string().c_str(), &p.output);
  if (p.run.valid() && p.progress) {
    std::string stage;
    {
      const std::lock_guard lock(p.progress->mutex);
      stage = p.progress->stage;
    }
    const std::uint64_t total = p.progress->total, done = p.progress->done;
    ImGui::ProgressBar(total > 0 ? float(double(done) / double(total)) : 0.0f, ImVec2(-1.0f, 0.0f),
                       stage.c_str());
    if (p.progress->cancel) {
      ImGui::TextDisabled("cancelling at the next tile");
    } else {
      if (ImGui::Button("Cancel")) p.progress->requestCancel();
      if (s.trace_keys) traceCancelButton(s);
    }
  } else if (ImGui::Button("Run (K)")) {
    startProcessing(s);
  }
  if (!p.message.empty()) ImGui::TextWrapped("%s", p.message.c_str());
}

}  // namespace parallax::viewer_internal
