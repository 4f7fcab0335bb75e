// The registration preview (`view SOURCE --register-with TARGET`, or the panel's Registration
// section): ICP of the cloud shown onto a target file (registration/cloud_registration.h) on a
// thread of its own, then both clouds coloured apart, the source before or after the transform
// (a toggle), with the RMS, the overlap and the matrix; the transform is written only when the
// user accepts it.
#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "io/point_file.h"
#include "registration/cloud_registration.h"
#include "render/draw_set_layers.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

std::string text(const std::array<char, 1024>& field) {
  return std::string(field.data());
}

void setText(std::array<char, 1024>& field, const std::string& value) {
  field.fill('\0');
  value.copy(field.data(), field.size() - 1);
}

void reportRegistration(Session& s, const std::string& message) {
  s.registration.message = message;
  std::fprintf(stderr, "parallax view: %s\n", message.c_str());
}

}  // namespace

void logRegistrationTransform(const char* what, const RigidTransform& transform) {
  std::string rows = std::string("parallax view: ") + what + ":";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      char number[40];
      std::snprintf(number, sizeof number, " %.17g", transform.m[std::size_t(r)][std::size_t(c)]);
      rows += number;
    }
  }
  std::fprintf(stderr, "%s\n", rows.c_str());
}

void startRegistration(Session& s, const RigidTransform& init) {
  RegistrationSession& r = s.registration;
  if (r.run.valid()) return;
  if (!s.cloud_points) {
    reportRegistration(
        s, "registration: needs a whole cloud shown (an octree's nodes are not registered)");
    return;
  }
  const std::string target_path = text(r.target_text);
  if (target_path.empty()) {
    reportRegistration(s, "registration: give the target file");
    return;
  }
  auto source = std::make_shared<const PointCloud>(s.cloud_points->clone());
  IcpOptions options;
  options.max_distance = r.max_distance;
  options.init = init;
  // The target the point pairs were picked on, when it is this one: not read again.
  std::shared_ptr<const PointCloud> loaded_target;
  if (r.pairs.target && r.pairs.target_path == std::filesystem::path(target_path)) {
    loaded_target = r.pairs.target;
  }
  const std::string source_name = s.loaded_name;
  r.result.reset();
  r.message = "registering " + source_name + " to " + target_path + " ...";
  r.run =
      std::async(std::launch::async, [source, target_path, options, source_name, loaded_target] {
        auto target = loaded_target
                          ? loaded_target
                          : std::make_shared<const PointCloud>(readPointFile(target_path));
        IcpResult result = registerClouds(*source, *target, options, source_name, target_path);
        return RegistrationRun{source, std::move(target), result};
      });
}

void updateRegistration(Session& s) {
  RegistrationSession& r = s.registration;
  if (r.start_requested && s.cloud_points) {
    r.start_requested = false;
    startRegistration(s);
  }
  updatePairPicking(s);
  if (!r.run.valid() || r.run.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  try {
    RegistrationRun run = r.run.get();
    r.source = std::move(run.source);
    r.target = std::move(run.target);
    r.result = run.result;
    // Each side uploaded on its own and drawn together, the target first: the sizes are the
    // target's spacing, where one cloud of both would halve it (or make it 0 for two copies).
    r.target_layer = std::make_unique<GpuPointCloud>(
        registrationPreviewSide(*r.target, RigidTransform{}, kPreviewTargetColor));
    r.before = std::make_unique<GpuPointCloud>(
        registrationPreviewSide(*r.source, RigidTransform{}, kPreviewSourceColor));
    r.after = std::make_unique<GpuPointCloud>(
        registrationPreviewSide(*r.source, r.result->transform, kPreviewSourceColor));
    r.before_set = withLayer(r.target_layer->drawSet(), r.before->drawSet());
    r.after_set = withLayer(r.target_layer->drawSet(), r.after->drawSet());
    r.shown = true;
    r.show_after = true;
    stopPairPicking(s);  // ICP's result is what is previewed now
    s.drawn.reset();
    char line[160];
    std::snprintf(line, sizeof line, "registered: rms %.6g, overlap %.4f, %u iterations",
                  r.result->rms, r.result->overlap, r.result->iterations);
    reportRegistration(s, line);
    logRegistrationTransform("registered transform", r.result->transform);
  } catch (const std::exception& e) {
    r.result.reset();
    reportRegistration(s, e.what());
  }
}

const DrawSet* registrationDrawSet(const Session& s) {
  if (const DrawSet* pairs = pairPickingDrawSet(s)) return pairs;
  const RegistrationSession& r = s.registration;
  if (!r.shown || !r.before || !r.after) return nullptr;
  return r.show_after ? &r.after_set : &r.before_set;
}

bool acceptRegistration(Session& s) {
  RegistrationSession& r = s.registration;
  if (!r.result) return false;
  const std::string path = text(r.output_text);
  if (path.empty()) {
    reportRegistration(s, "registration: give the file to write the transform to");
    return false;
  }
  try {
    writeRigidTransform(r.result->transform, path);
    reportRegistration(s, "wrote the transform to " + path);
    return true;
  } catch (const std::exception& e) {
    reportRegistration(s, e.what());
    return false;
  }
}

void prepareRegistration(Session& s, const std::filesystem::path& target,
                         const std::filesystem::path& output, bool pick_pairs) {
  setText(s.registration.target_text, target.string());
  setText(s.registration.output_text, output.string());
  s.registration.start_requested = !target.empty() && !pick_pairs;
  s.registration.pairs_requested = !target.empty() && pick_pairs;
}

void drawRegistrationPanel(Session& s) {
  RegistrationSession& r = s.registration;
  ImGui::Separator();
  ImGui::TextDisabled("Registration");
  ImGui::InputText("target file", r.target_text.data(), r.target_text.size());
  ImGui::InputDouble("max distance", &r.max_distance, 0.0, 0.0, "%.6g");
  if (r.max_distance < 0.0) r.max_distance = 0.0;
  if (r.run.valid()) {
    ImGui::TextUnformatted("running ICP ...");
  } else if (ImGui::Button("Register the cloud to it")) {
    startRegistration(s);
  }
  drawPairPickingPanel(s);
  if (r.result) {
    const IcpResult& result = *r.result;
    ImGui::Text("rms %.6g, overlap %.4f (%llu pairs)", result.rms, result.overlap,
                static_cast<unsigned long long>(result.correspondences));
    ImGui::Text("rotation %.6g deg, translation %.6g", result.transform.angleDegrees(),
                result.transform.translationLength());
    for (const auto& row : result.transform.m) {
      ImGui::Text("%12.6f %12.6f %12.6f %14.6f", row[0], row[1], row[2], row[3]);
    }
    if (ImGui::Checkbox("show both (source orange, target blue)", &r.shown)) s.drawn.reset();
    if (r.shown) {
      int which = r.show_after ? 1 : 0;
      bool changed = ImGui::RadioButton("before", &which, 0);
      ImGui::SameLine();
      changed = ImGui::RadioButton("after", &which, 1) || changed;
      if (changed) {
        r.show_after = which == 1;
        s.drawn.reset();
      }
    }
    ImGui::InputText("transform file", r.output_text.data(), r.output_text.size());
    if (ImGui::Button("Accept: write the transform")) acceptRegistration(s);
  }
  if (!r.message.empty()) ImGui::TextWrapped("%s", r.message.c_str());
}

}  // namespace parallax::viewer_internal
