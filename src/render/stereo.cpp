#include "render/stereo.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <utility>

namespace parallax {

namespace {

struct ModeName {
  StereoMode mode;
  std::string_view name;
};

constexpr std::array<ModeName, 8> kModeNames{{
    {StereoMode::Mono, "mono"},
    {StereoMode::SideBySide, "sbs"},
    {StereoMode::SideBySideSqueezed, "sbs-squeezed"},
    {StereoMode::TopBottom, "tb"},
    {StereoMode::Anaglyph, "anaglyph"},
    {StereoMode::AnaglyphDubois, "anaglyph-dubois"},
    {StereoMode::Interlaced, "interlaced"},
    {StereoMode::QuadBuffer, "quad-buffer"},
}};

Composition compositionOf(StereoMode mode) {
  switch (mode) {
    case StereoMode::Anaglyph:
      return Composition::Anaglyph;
    case StereoMode::AnaglyphDubois:
      return Composition::AnaglyphDubois;
    case StereoMode::Interlaced:
      return Composition::Interlaced;
    case StereoMode::QuadBuffer:
      return Composition::QuadBuffer;
    default:
      return Composition::Direct;
  }
}

}  // namespace

double autoConvergence(const Camera& camera) {
  return camera.pivotDepth();
}

double autoEyeSeparation(double convergence) {
  return convergence / 30.0;
}

StereoSettings resolvedStereo(const StereoSettings& settings, const Camera& camera) {
  StereoSettings resolved = settings;
  if (!(resolved.convergence > 0)) resolved.convergence = autoConvergence(camera);
  if (!(resolved.eye_separation > 0)) {
    resolved.eye_separation = autoEyeSeparation(resolved.convergence);
  }
  return resolved;
}

StereoEyes stereoEyes(const Camera& camera, double separation, double convergence, bool swap) {
  assert(convergence > 0 && "stereoEyes needs a positive convergence distance");
  StereoEyes eyes{camera, camera};
  const double half = separation / 2;
  // Both eyes keep the camera's orientation (parallel view directions) and pivot.
  eyes.left.position = camera.position - camera.right() * half;
  eyes.right.position = camera.position + camera.right() * half;
  eyes.left.off_axis_skew = -half / convergence;
  eyes.right.off_axis_skew = half / convergence;
  if (swap) std::swap(eyes.left, eyes.right);
  return eyes;
}

StereoFrame stereoFrame(const Camera& camera, const StereoSettings& settings, int width,
                        int height) {
  StereoFrame frame;
  if (settings.mode == StereoMode::Mono) {
    frame.views.push_back({camera, {0, 0, width, height}});
    frame.views.back().output = frame.views.back().viewport;
    return frame;
  }
  const StereoSettings s = resolvedStereo(settings, camera);
  const StereoEyes eyes = stereoEyes(camera, s.eye_separation, s.convergence, s.swap_eyes);
  frame.composition = compositionOf(s.mode);
  // At least a pixel each, so that even a 1-pixel output gets a valid projection.
  const int half_width = std::max(width / 2, 1), half_height = std::max(height / 2, 1);
  switch (s.mode) {
    case StereoMode::SideBySide:
      frame.views = {{eyes.left, {0, 0, half_width, height}},
                     {eyes.right, {half_width, 0, std::max(width - half_width, 1), height}}};
      break;
    case StereoMode::SideBySideSqueezed: {
      // Anamorphic: the projection keeps the whole output's aspect in a half-width viewport.
      const double aspect = double(width) / std::max(height, 1);
      frame.views = {
          {eyes.left, {0, 0, half_width, height}, aspect},
          {eyes.right, {half_width, 0, std::max(width - half_width, 1), height}, aspect}};
      break;
    }
    case StereoMode::TopBottom:
      // OpenGL's rows go up: the top half starts at height - half_height.
      frame.views = {{eyes.left, {0, height - half_height, width, half_height}},
                     {eyes.right, {0, 0, width, std::max(height - half_height, 1)}}};
      break;
    default:  // composed modes: both eyes full size in a double-width canvas
      frame.views = {{eyes.left, {0, 0, width, height}}, {eyes.right, {width, 0, width, height}}};
      // Each eye's picture covers the whole output once composed.
      for (View& view : frame.views) view.output = {0, 0, width, height};
      return frame;
  }
  for (View& view : frame.views) view.output = view.viewport;  // drawn straight to the output
  return frame;
}

std::optional<StereoMode> parseStereoMode(std::string_view name) {
  for (const ModeName& entry : kModeNames) {
    if (entry.name == name) return entry.mode;
  }
  return std::nullopt;
}

std::string_view stereoModeName(StereoMode mode) {
  for (const ModeName& entry : kModeNames) {
    if (entry.mode == mode) return entry.name;
  }
  return "mono";
}

std::string stereoModeNames() {
  std::string names;
  for (const ModeName& entry : kModeNames) {
    if (!names.empty()) names += '|';
    names += entry.name;
  }
  return names;
}

const std::vector<StereoMode>& allStereoModes() {
  static const std::vector<StereoMode> modes = [] {
    std::vector<StereoMode> result;
    for (const ModeName& entry : kModeNames) result.push_back(entry.mode);
    return result;
  }();
  return modes;
}

}  // namespace parallax
