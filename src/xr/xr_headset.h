// An OpenXR session through the Khronos loader: a stereo headset (XR_VIEW_CONFIGURATION_TYPE_
// PRIMARY_STEREO) drawn through OpenGL in the application's EGL context (XR_MNDX_egl_enable), one
// side-by-side swapchain for both eyes (left eye at x 0, right eye at x width), eyes located in
// the STAGE reference space (LOCAL where the runtime has no stage).
//
// The session's lifecycle follows the specification's state machine: READY begins it, STOPPING
// ends it, EXITING or LOSS_PENDING closes it; frames are waited for, begun and ended in every
// running state, with the projection layer submitted only when the runtime says shouldRender.
#pragma once

#include <epoxy/gl.h>

#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "render/view.h"
#include "xr/stage_mapping.h"
#include "xr/xr_input.h"

namespace parallax {

// No runtime, no headset, or a call the runtime failed: the message names the runtime that was
// looked for (XR_RUNTIME_JSON or the active_runtime.json files) and the call and its result.
class XrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One eye of a frame: as the runtime located it at the predicted display time, and its rectangle
// of the frame's framebuffer (bottom-left origin).
struct XrEye {
  EyeFov fov;
  StagePose pose;
  Viewport viewport;
};

struct XrFrameInfo {
  std::span<const XrEye> eyes;  // left eye first
  GLuint framebuffer = 0;       // both eyes' picture: width x height, eyes side by side
  int width = 0, height = 0;
  long long index = 0;  // frames drawn before this one
  // The controllers at the frame's predicted display time, the head between the eyes, the
  // display period (xr_actions.h); hands are untracked while the session is not focused.
  const XrInput* input = nullptr;
};

struct XrSessionStats {
  long long frames_drawn = 0;  // frames with a submitted projection layer
  long long frames_ended = 0;  // every xrEndFrame
  std::string runtime;         // the runtime's name and version
  std::string system;          // the headset's name
  std::string binding;         // how frames reach the runtime: "EGL (...)" or "GLX (...)"
  int eye_width = 0, eye_height = 0;
};

class XrHeadset {
 public:
  // Needs the context the frames are drawn with current on this thread for its whole life: a
  // headless EGL one (render/gl_context.h createHeadless) or a window's GLX one (the mirror,
  // viewer/xr_mirror_window.h). Throws XrError.
  explicit XrHeadset(const std::string& application_name);
  ~XrHeadset();
  XrHeadset(const XrHeadset&) = delete;
  XrHeadset& operator=(const XrHeadset&) = delete;

  // The runtime's recommended size of one eye's picture, in pixels.
  int eyeWidth() const;
  int eyeHeight() const;

  // Runs the session until the runtime ends it (or `stop_after` frames were drawn, 0: never),
  // calling `draw` for every frame the runtime wants drawn. Throws XrError.
  XrSessionStats run(const std::function<void(const XrFrameInfo&)>& draw, long long stop_after = 0);
  // Asks the runtime to end the session after the current frame (the mirror window was closed);
  // run() returns once it has.
  void requestExit() { exit_wanted_ = true; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  bool exit_wanted_ = false;
};

// Where the loader looks for a runtime, for messages: "XR_RUNTIME_JSON=<path>" or the
// active_runtime.json files of the XDG configuration folders.
std::string xrRuntimeLookedFor();

}  // namespace parallax
