#include "xr/xr_actions.h"

#include <cstdio>
#include <string>
#include <vector>

#include "xr/xr_headset.h"

namespace parallax {
namespace {

XrPath pathOf(XrInstance instance, const std::string& text) {
  XrPath path = XR_NULL_PATH;
  xrCheck(instance, xrStringToPath(instance, text.c_str(), &path),
          ("xrStringToPath(" + text + ")").c_str());
  return path;
}

XrAction makeAction(XrInstance instance, XrActionSet set, const char* name, const char* label,
                    XrActionType type, const std::array<XrPath, 2>& hands) {
  XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
  std::snprintf(info.actionName, sizeof(info.actionName), "%s", name);
  std::snprintf(info.localizedActionName, sizeof(info.localizedActionName), "%s", label);
  info.actionType = type;
  info.countSubactionPaths = uint32_t(hands.size());
  info.subactionPaths = hands.data();
  XrAction action = XR_NULL_HANDLE;
  xrCheck(instance, xrCreateAction(set, &info, &action), "xrCreateAction");
  return action;
}

StagePose poseOf(const XrPosef& p) {
  StagePose out;
  out.position = {p.position.x, p.position.y, p.position.z};
  out.orientation = glm::dquat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  return out;
}

}  // namespace

XrActions::XrActions(XrInstance instance, XrSession session)
    : instance_(instance), session_(session) {
  XrActionSetCreateInfo set_info{XR_TYPE_ACTION_SET_CREATE_INFO};
  std::snprintf(set_info.actionSetName, sizeof(set_info.actionSetName), "parallax");
  std::snprintf(set_info.localizedActionSetName, sizeof(set_info.localizedActionSetName),
                "Parallax");
  xrCheck(instance, xrCreateActionSet(instance, &set_info, &set_), "xrCreateActionSet");
  const char* const hand_names[2] = {"left", "right"};
  for (int h = 0; h < 2; ++h) {
    hand_paths_[h] = pathOf(instance, std::string("/user/hand/") + hand_names[h]);
  }
  grip_ = makeAction(instance, set_, "grip", "Hand", XR_ACTION_TYPE_POSE_INPUT, hand_paths_);
  aim_ = makeAction(instance, set_, "aim", "Laser", XR_ACTION_TYPE_POSE_INPUT, hand_paths_);
  trigger_ =
      makeAction(instance, set_, "pick", "Pick a point", XR_ACTION_TYPE_FLOAT_INPUT, hand_paths_);
  squeeze_ =
      makeAction(instance, set_, "grab", "Grab the world", XR_ACTION_TYPE_FLOAT_INPUT, hand_paths_);
  thumbstick_ = makeAction(instance, set_, "move", "Fly (left), turn (right)",
                           XR_ACTION_TYPE_VECTOR2F_INPUT, hand_paths_);
  primary_ =
      makeAction(instance, set_, "teleport", "Teleport", XR_ACTION_TYPE_BOOLEAN_INPUT, hand_paths_);
  secondary_ = makeAction(instance, set_, "tool",
                          "Next measurement tool, close an area; held: delete the last",
                          XR_ACTION_TYPE_BOOLEAN_INPUT, hand_paths_);

  struct Binding {
    XrAction action;
    const char* input;  // under /user/hand/<hand>/input/
    int hand = -1;      // -1: both hands
  };
  struct Profile {
    const char* path;
    std::vector<Binding> bindings;
  };
  const Profile profiles[] = {
      {"/interaction_profiles/khr/simple_controller",
       {{grip_, "grip/pose"},
        {aim_, "aim/pose"},
        {trigger_, "select/click"},
        {squeeze_, "menu/click"}}},
      {"/interaction_profiles/oculus/touch_controller",
       {{grip_, "grip/pose"},
        {aim_, "aim/pose"},
        {trigger_, "trigger/value"},
        {squeeze_, "squeeze/value"},
        {thumbstick_, "thumbstick"},
        {primary_, "x/click", kLeftHand},
        {primary_, "a/click", kRightHand},
        {secondary_, "y/click", kLeftHand},
        {secondary_, "b/click", kRightHand}}},
      {"/interaction_profiles/valve/index_controller",
       {{grip_, "grip/pose"},
        {aim_, "aim/pose"},
        {trigger_, "trigger/value"},
        {squeeze_, "squeeze/value"},
        {thumbstick_, "thumbstick"},
        {primary_, "a/click"},
        {secondary_, "b/click"}}},
  };
  for (const Profile& profile : profiles) {
    std::vector<XrActionSuggestedBinding> suggested;
    for (const Binding& b : profile.bindings) {
      for (int h = 0; h < 2; ++h) {
        if (b.hand >= 0 && b.hand != h) continue;
        suggested.push_back({b.action, pathOf(instance, std::string("/user/hand/") + hand_names[h] +
                                                            "/input/" + b.input)});
      }
    }
    XrInteractionProfileSuggestedBinding info{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    info.interactionProfile = pathOf(instance, profile.path);
    info.countSuggestedBindings = uint32_t(suggested.size());
    info.suggestedBindings = suggested.data();
    const XrResult result = xrSuggestInteractionProfileBindings(instance, &info);
    // A runtime may not know every profile (XR_ERROR_PATH_UNSUPPORTED): it then uses another.
    if (result != XR_ERROR_PATH_UNSUPPORTED) {
      xrCheck(instance, result, "xrSuggestInteractionProfileBindings");
    }
  }
  XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
  attach.countActionSets = 1;
  attach.actionSets = &set_;
  xrCheck(instance, xrAttachSessionActionSets(session, &attach), "xrAttachSessionActionSets");
  for (int h = 0; h < 2; ++h) {
    XrActionSpaceCreateInfo space{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    space.subactionPath = hand_paths_[h];
    space.poseInActionSpace.orientation.w = 1.0f;
    space.action = grip_;
    xrCheck(instance, xrCreateActionSpace(session, &space, &grip_spaces_[h]),
            "xrCreateActionSpace");
    space.action = aim_;
    xrCheck(instance, xrCreateActionSpace(session, &space, &aim_spaces_[h]), "xrCreateActionSpace");
  }
}

XrActions::~XrActions() {
  for (XrSpace space : grip_spaces_) {
    if (space) xrDestroySpace(space);
  }
  for (XrSpace space : aim_spaces_) {
    if (space) xrDestroySpace(space);
  }
  // Destroying the set destroys its actions.
  if (set_) xrDestroyActionSet(set_);
}

void XrActions::read(XrSpace space, XrTime time, bool focused, XrInput& input) {
  for (XrHandInput& hand : input.hands) hand = XrHandInput{};
  if (!focused) return;
  XrActiveActionSet active{set_, XR_NULL_PATH};
  XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
  sync.countActiveActionSets = 1;
  sync.activeActionSets = &active;
  const XrResult synced = xrSyncActions(session_, &sync);
  xrCheck(instance_, synced, "xrSyncActions");
  if (synced == XR_SESSION_NOT_FOCUSED) return;
  for (int h = 0; h < 2; ++h) {
    XrHandInput& hand = input.hands[h];
    XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
    get.subactionPath = hand_paths_[h];
    const XrSpaceLocationFlags valid =
        XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT;
    XrSpaceLocation grip{XR_TYPE_SPACE_LOCATION}, aim{XR_TYPE_SPACE_LOCATION};
    xrCheck(instance_, xrLocateSpace(grip_spaces_[h], space, time, &grip), "xrLocateSpace");
    xrCheck(instance_, xrLocateSpace(aim_spaces_[h], space, time, &aim), "xrLocateSpace");
    hand.tracked = (grip.locationFlags & valid) == valid && (aim.locationFlags & valid) == valid;
    if (!hand.tracked) continue;
    hand.grip = poseOf(grip.pose);
    hand.aim = poseOf(aim.pose);
    XrActionStateFloat value{XR_TYPE_ACTION_STATE_FLOAT};
    get.action = trigger_;
    xrCheck(instance_, xrGetActionStateFloat(session_, &get, &value), "xrGetActionStateFloat");
    hand.trigger = value.isActive ? value.currentState : 0.0f;
    value = {XR_TYPE_ACTION_STATE_FLOAT};
    get.action = squeeze_;
    xrCheck(instance_, xrGetActionStateFloat(session_, &get, &value), "xrGetActionStateFloat");
    hand.squeeze = value.isActive ? value.currentState : 0.0f;
    XrActionStateVector2f stick{XR_TYPE_ACTION_STATE_VECTOR2F};
    get.action = thumbstick_;
    xrCheck(instance_, xrGetActionStateVector2f(session_, &get, &stick),
            "xrGetActionStateVector2f");
    if (stick.isActive) hand.thumbstick = {stick.currentState.x, stick.currentState.y};
    XrActionStateBoolean button{XR_TYPE_ACTION_STATE_BOOLEAN};
    get.action = primary_;
    xrCheck(instance_, xrGetActionStateBoolean(session_, &get, &button), "xrGetActionStateBoolean");
    hand.primary = button.isActive && button.currentState;
    button = {XR_TYPE_ACTION_STATE_BOOLEAN};
    get.action = secondary_;
    xrCheck(instance_, xrGetActionStateBoolean(session_, &get, &button), "xrGetActionStateBoolean");
    hand.secondary = button.isActive && button.currentState;
  }
}

}  // namespace parallax
