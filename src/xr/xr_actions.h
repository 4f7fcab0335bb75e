// The controllers through the OpenXR action system (issue 24, item 4): one action set
// ("parallax") with a grip pose, an aim pose, a trigger, a squeeze, a thumbstick, a primary and a
// secondary button for each hand (subaction paths /user/hand/left and /user/hand/right),
// bindings suggested for three interaction profiles:
//   khr/simple_controller   select/click: trigger, menu/click: squeeze (no stick, no button)
//   oculus/touch_controller trigger/value, squeeze/value, thumbstick, x/click (left), a/click,
//                           y/click (left), b/click (secondary)
//   valve/index_controller  trigger/value, squeeze/value, thumbstick, a/click, b/click
// Private to src/xr (it includes the OpenXR headers; xr_input.h is what the rest sees).
#pragma once

#include <openxr/openxr.h>

#include <array>

#include "xr/xr_input.h"

namespace parallax {

// Throws XrError naming the call, its result and the runtime where `result` is a failure
// (xr_headset.cpp).
void xrCheck(XrInstance instance, XrResult result, const char* call);

class XrActions {
 public:
  // Creates the set, its actions and spaces, suggests the bindings and attaches the set to the
  // session. Throws XrError.
  XrActions(XrInstance instance, XrSession session);
  ~XrActions();
  XrActions(const XrActions&) = delete;
  XrActions& operator=(const XrActions&) = delete;

  // Syncs the actions (only while the session is focused: input belongs to the focused
  // application) and fills `input.hands` with the hands' poses in `space` at `time` and their
  // buttons. An unfocused session's hands are untracked. Throws XrError.
  void read(XrSpace space, XrTime time, bool focused, XrInput& input);

 private:
  XrInstance instance_ = XR_NULL_HANDLE;
  XrSession session_ = XR_NULL_HANDLE;
  XrActionSet set_ = XR_NULL_HANDLE;
  XrAction grip_ = XR_NULL_HANDLE, aim_ = XR_NULL_HANDLE, trigger_ = XR_NULL_HANDLE,
           squeeze_ = XR_NULL_HANDLE, thumbstick_ = XR_NULL_HANDLE, primary_ = XR_NULL_HANDLE,
           secondary_ = XR_NULL_HANDLE;
  std::array<XrPath, 2> hand_paths_{XR_NULL_PATH, XR_NULL_PATH};
  std::array<XrSpace, 2> grip_spaces_{XR_NULL_HANDLE, XR_NULL_HANDLE};
  std::array<XrSpace, 2> aim_spaces_{XR_NULL_HANDLE, XR_NULL_HANDLE};
};

}  // namespace parallax
