// Stereo as a list of views: the off-axis eye cameras of a camera, and where each eye's picture
// goes in every display mode.
//
// Off-axis (asymmetric frustum) stereo, never toe-in: the eyes sit at -separation/2 (left) and
// +separation/2 (right) along the camera's right vector, both look along the camera's forward
// direction, and each eye's frustum is skewed (Camera::off_axis_skew = eye offset / convergence)
// so that the plane at the convergence distance has zero parallax. A point at depth d (along
// forward) then lands f * separation * (1/convergence - 1/d) pixels further right in the right
// eye than in the left, f = viewport height / (2 tan(fov_y / 2)) the focal length in pixels:
// points behind the convergence plane appear behind the screen. Toe-in (eyes rotated towards the
// convergence point) would add vertical parallax at the picture's corners, which hurts.
//
// Orthographic cameras have no perspective parallax; the eyes get the same shear of eye space
// (x += skew * depth), which gives a parallax linear in depth, zero at the convergence distance,
// with the slope a perspective camera has there when its view at that distance is ortho_height
// high (see NOTES.md).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "render/camera.h"
#include "render/view.h"

namespace parallax {

enum class StereoMode {
  Mono,
  SideBySide,          // left eye in the left half, each half a view of its own aspect
  SideBySideSqueezed,  // each eye at the whole output's aspect, squeezed to half width (3D TVs)
  TopBottom,           // left eye in the top half, each half a view of its own aspect
  Anaglyph,            // red from the left eye, green and blue from the right eye
  AnaglyphDubois,      // Dubois' least-squares red-cyan matrices (less ghosting)
  Interlaced,          // rows 0, 2, 4... from the top: left eye; odd rows: right eye
  QuadBuffer,          // GL_STEREO: the left and right back buffers of a stereo window
};

// How the eyes' pictures become the output (Renderer::render).
enum class Composition {
  Direct,          // the views are drawn straight into their rectangles of the output
  Anaglyph,        // the two eyes drawn side by side into a double-width canvas, then composed
  AnaglyphDubois,  // as Anaglyph, with Dubois' matrices
  Interlaced,      // as Anaglyph, row by row
  QuadBuffer,      // as Anaglyph, then each half into GL_BACK_LEFT / GL_BACK_RIGHT
};

struct StereoSettings {
  StereoMode mode = StereoMode::Mono;
  // Scene units; 0 or less: automatic (see autoConvergence, autoEyeSeparation).
  double eye_separation = 0.0;
  double convergence = 0.0;
  bool swap_eyes = false;  // the left eye's picture goes where the right one's would, and back

  friend bool operator==(const StereoSettings&, const StereoSettings&) = default;
};

struct StereoEyes {
  Camera left, right;
};

// The default convergence: the pivot's depth, so that what the user orbits around sits on the
// screen plane, where the eyes are most comfortable.
double autoConvergence(const Camera& camera);
// The default separation: convergence / 30, the "1/30 rule" of stereo photography: with the
// screen at the convergence plane, the nearest comfortable object is at about half that
// distance; anything from infinity to there keeps the parallax within about 1/30 of the view's
// width at 60 degrees, the comfort budget usually quoted for desktop monitors.
double autoEyeSeparation(double convergence);
// Settings with automatic values resolved for this camera.
StereoSettings resolvedStereo(const StereoSettings& settings, const Camera& camera);

// The two eye cameras (positions, skews; orientation, projection and field of view copied).
// `separation` and `convergence` in scene units, convergence > 0. With `swap`, the cameras
// change places (the right eye's camera is returned as `left`).
StereoEyes stereoEyes(const Camera& camera, double separation, double convergence, bool swap);

// The views one frame draws for `mode` at an output of width x height pixels (mono: one view,
// stereo: the left eye's first), the size of the canvas they are drawn into, and how the canvas
// becomes the output. Direct: canvas = output. Otherwise the canvas is 2 * width x height with
// the left eye's picture at x 0 and the right one's at x width.
struct StereoFrame {
  std::vector<View> views;
  Composition composition = Composition::Direct;
};
StereoFrame stereoFrame(const Camera& camera, const StereoSettings& settings, int width,
                        int height);

// "mono", "sbs", "sbs-squeezed", "tb", "anaglyph", "anaglyph-dubois", "interlaced",
// "quad-buffer"; std::nullopt for another name.
std::optional<StereoMode> parseStereoMode(std::string_view name);
std::string_view stereoModeName(StereoMode mode);
// "mono|sbs|...|quad-buffer", for help texts and errors.
std::string stereoModeNames();
// Every mode, in the order the viewer cycles through them.
const std::vector<StereoMode>& allStereoModes();

}  // namespace parallax
