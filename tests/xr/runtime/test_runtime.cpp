// A small OpenXR 1.0 runtime for tests (issue 24, item 5), written from the OpenXR specification
// and its loader document: a stereo headset whose views, image size and frame count come from
// PARALLAX_XR_TEST (test_runtime_config.h). It offers XR_KHR_opengl_enable and
// XR_MNDX_egl_enable, makes swapchain images as GL textures in the application's context (which
// the application keeps current on the thread that calls xrCreateSwapchain and xrEndFrame, as it
// does in a single-threaded renderer), and on every xrEndFrame writes each projection view the
// application submitted as DIR/frame_F_view_V.png (top row first) with DIR/frame_F.json (the
// pose, fov and image rect submitted). Frames are paced at 90 Hz (xrWaitFrame blocks until the
// display time it predicted last), as a real compositor paces them. After the configured number
// of frames it takes the session through focus loss (VISIBLE), SYNCHRONIZED and STOPPING; after
// xrEndSession, IDLE then EXITING.
//
// One instance and one session at a time; no real tracking: the controllers are scripted per
// frame by the configuration's "controllers" (poses and inputs), read through the action system
// as the application's suggested bindings for the configured interaction profile route them. What
// an application may not do, the core validation layer reports; this runtime only checks what it
// needs to stay sane and answers XR_ERROR_VALIDATION_FAILURE otherwise.
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define XR_USE_GRAPHICS_API_OPENGL
#define XR_USE_PLATFORM_EGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "test_runtime_config.h"

// The loader's negotiation interface (OpenXR loader specification, "Runtime Negotiation"); the
// Debian headers do not ship loader_interfaces.h, so its types are declared here as specified.
enum XrLoaderInterfaceStructs {
  XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
  XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
  XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
};
struct XrNegotiateLoaderInfo {
  XrLoaderInterfaceStructs structType;
  uint32_t structVersion;
  size_t structSize;
  uint32_t minInterfaceVersion;
  uint32_t maxInterfaceVersion;
  XrVersion minApiVersion;
  XrVersion maxApiVersion;
};
struct XrNegotiateRuntimeRequest {
  XrLoaderInterfaceStructs structType;
  uint32_t structVersion;
  size_t structSize;
  uint32_t runtimeInterfaceVersion;
  XrVersion runtimeApiVersion;
  PFN_xrGetInstanceProcAddr getInstanceProcAddr;
};
constexpr uint32_t kLoaderInfoStructVersion = 1, kRuntimeInfoStructVersion = 1;
constexpr uint32_t kLoaderRuntimeVersion = 1;

namespace {

using parallax::xr_test::RuntimeConfig;

constexpr const char* kExtensions[] = {XR_KHR_OPENGL_ENABLE_EXTENSION_NAME,
                                       XR_MNDX_EGL_ENABLE_EXTENSION_NAME};
constexpr XrSystemId kSystemId = 1;
constexpr XrDuration kFramePeriod = 11'111'111;  // 90 Hz
constexpr int kSwapchainImages = 3;

struct Pose {
  glm::quat orientation{1, 0, 0, 0};
  glm::vec3 position{0.0f};
};
Pose toPose(const XrPosef& p) {
  return {glm::quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z),
          glm::vec3(p.position.x, p.position.y, p.position.z)};
}
XrPosef toXr(const Pose& p) {
  XrPosef out;
  out.orientation = {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w};
  out.position = {p.position.x, p.position.y, p.position.z};
  return out;
}
// a * b: b's frame expressed in a's parent.
Pose compose(const Pose& a, const Pose& b) {
  return {a.orientation * b.orientation, a.position + a.orientation * b.position};
}
Pose inverse(const Pose& p) {
  const glm::quat inv = glm::conjugate(p.orientation);
  return {inv, -(inv * p.position)};
}

enum class Binding { None, OpenGlXlib, Egl };

struct Swapchain {
  std::vector<GLuint> textures;
  uint32_t width = 0, height = 0, array_size = 1;
  int64_t format = 0;
  uint32_t next = 0;  // the image the next acquire returns
  int acquired = 0;   // images acquired and not yet released
  int released = -1;  // the image last released (what a layer shows)
  Binding binding = Binding::None;
};

struct ActionSet {
  std::string name;
  bool attached = false;
};
struct Action {
  XrActionType type = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::string name;
};

struct Space {
  XrReferenceSpaceType type = XR_REFERENCE_SPACE_TYPE_STAGE;
  const Action* action = nullptr;  // an action space: where its pose action's hand is
  XrPath subaction = XR_NULL_PATH;
  Pose pose;  // poseInReferenceSpace or poseInActionSpace
};

struct Session {
  XrSessionState state = XR_SESSION_STATE_IDLE;
  Binding binding = Binding::None;
  bool running = false;
  bool frame_begun = false;
  bool exit_requested = false;
  uint64_t frames_waited = 0, frames_ended = 0;
  XrTime last_display_time = 0;  // the display time xrWaitFrame predicted last (0: none yet)
  bool actions_attached = false;
  // The controllers' state as of the last xrSyncActions (none before it, or while unfocused).
  const parallax::xr_test::ControllerFrame* controllers = nullptr;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

struct Instance {
  RuntimeConfig config;
  std::deque<XrEventDataBuffer> events;
  std::vector<std::string> paths{""};  // XrPath n names paths[n]; 0 is XR_NULL_PATH
  // The application's suggested bindings, by interaction profile: (action, input path).
  std::map<XrPath, std::vector<std::pair<const Action*, XrPath>>> suggested;
  std::unique_ptr<Session> session;
};

// One instance at a time; handles are pointers to these objects (never dereferenced unchecked).
std::unique_ptr<Instance> g_instance;

Instance* instanceOf(XrInstance handle) {
  return g_instance && reinterpret_cast<Instance*>(handle) == g_instance.get() ? g_instance.get()
                                                                               : nullptr;
}
Session* sessionOf(XrSession handle) {
  return g_instance && g_instance->session &&
                 reinterpret_cast<Session*>(handle) == g_instance->session.get()
             ? g_instance->session.get()
             : nullptr;
}

void pushState(Session& session, XrSessionState state) {
  session.state = state;
  XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER};
  auto* changed = reinterpret_cast<XrEventDataSessionStateChanged*>(&buffer);
  changed->type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED;
  changed->next = nullptr;
  changed->session = reinterpret_cast<XrSession>(&session);
  changed->state = state;
  changed->time = 0;
  g_instance->events.push_back(buffer);
}

// The two-call idiom of the specification ("Buffer Size Parameters").
template <typename T, typename Out, typename Fill>
XrResult enumerate(uint32_t capacity, uint32_t* count, Out* out, const std::vector<T>& items,
                   Fill fill) {
  if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *count = uint32_t(items.size());
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < items.size()) return XR_ERROR_SIZE_INSUFFICIENT;
  for (std::size_t i = 0; i < items.size(); ++i) fill(out[i], items[i]);
  return XR_SUCCESS;
}

XrTime now(const Session& session) {
  return XrTime(std::chrono::duration_cast<std::chrono::nanoseconds>(
                    std::chrono::steady_clock::now() - session.start)
                    .count()) +
         1'000'000'000;
}

// --- instance ------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL enumerateInstanceExtensionProperties(
    const char* layer, uint32_t capacity, uint32_t* count, XrExtensionProperties* properties) {
  if (layer != nullptr) return XR_ERROR_API_LAYER_NOT_PRESENT;
  const std::vector<const char*> names(std::begin(kExtensions), std::end(kExtensions));
  return enumerate(capacity, count, properties, names,
                   [](XrExtensionProperties& out, const char* name) {
                     std::snprintf(out.extensionName, sizeof(out.extensionName), "%s", name);
                     out.extensionVersion = 1;
                   });
}

XRAPI_ATTR XrResult XRAPI_CALL createInstance(const XrInstanceCreateInfo* info,
                                              XrInstance* instance) {
  if (g_instance) return XR_ERROR_LIMIT_REACHED;
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    bool known = false;
    for (const char* name : kExtensions)
      known |= std::strcmp(name, info->enabledExtensionNames[i]) == 0;
    if (!known) return XR_ERROR_EXTENSION_NOT_PRESENT;
  }
  auto created = std::make_unique<Instance>();
  try {
    created->config = parallax::xr_test::loadRuntimeConfig();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Parallax test runtime: %s\n", e.what());
    return XR_ERROR_RUNTIME_FAILURE;
  }
  g_instance = std::move(created);
  *instance = reinterpret_cast<XrInstance>(g_instance.get());
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL destroyInstance(XrInstance instance) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  g_instance.reset();
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL getInstanceProperties(XrInstance instance,
                                                     XrInstanceProperties* properties) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  properties->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
  std::snprintf(properties->runtimeName, sizeof(properties->runtimeName), "Parallax test runtime");
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL pollEvent(XrInstance instance, XrEventDataBuffer* event) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (in->events.empty()) return XR_EVENT_UNAVAILABLE;
  *event = in->events.front();
  in->events.pop_front();
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL resultToString(XrInstance, XrResult value,
                                              char buffer[XR_MAX_RESULT_STRING_SIZE]) {
  std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_RESULT_%d", int(value));
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL structureTypeToString(XrInstance, XrStructureType value,
                                                     char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
  std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_STRUCTURE_TYPE_%d", int(value));
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL stringToPath(XrInstance instance, const char* string, XrPath* path) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (string[0] != '/') return XR_ERROR_PATH_FORMAT_INVALID;
  for (std::size_t i = 1; i < in->paths.size(); ++i) {
    if (in->paths[i] == string) {
      *path = XrPath(i);
      return XR_SUCCESS;
    }
  }
  in->paths.emplace_back(string);
  *path = XrPath(in->paths.size() - 1);
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL pathToString(XrInstance instance, XrPath path, uint32_t capacity,
                                            uint32_t* count, char* buffer) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (path == XR_NULL_PATH || path >= in->paths.size()) return XR_ERROR_PATH_INVALID;
  const std::string& s = in->paths[path];
  *count = uint32_t(s.size() + 1);
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < s.size() + 1) return XR_ERROR_SIZE_INSUFFICIENT;
  std::memcpy(buffer, s.c_str(), s.size() + 1);
  return XR_SUCCESS;
}

// --- system --------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL getSystem(XrInstance instance, const XrSystemGetInfo* info,
                                         XrSystemId* system) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) {
    return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
  }
  *system = kSystemId;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL getSystemProperties(XrInstance instance, XrSystemId system,
                                                   XrSystemProperties* properties) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  properties->systemId = kSystemId;
  properties->vendorId = 0;
  std::snprintf(properties->systemName, sizeof(properties->systemName), "Parallax test headset");
  properties->graphicsProperties.maxSwapchainImageWidth = 16384;
  properties->graphicsProperties.maxSwapchainImageHeight = 16384;
  properties->graphicsProperties.maxLayerCount = XR_MIN_COMPOSITION_LAYERS_SUPPORTED;
  properties->trackingProperties.orientationTracking = XR_TRUE;
  properties->trackingProperties.positionTracking = XR_TRUE;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL enumerateEnvironmentBlendModes(XrInstance instance,
                                                              XrSystemId system,
                                                              XrViewConfigurationType type,
                                                              uint32_t capacity, uint32_t* count,
                                                              XrEnvironmentBlendMode* modes) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  const std::vector<XrEnvironmentBlendMode> items{XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
  return enumerate(capacity, count, modes, items,
                   [](XrEnvironmentBlendMode& out, XrEnvironmentBlendMode m) { out = m; });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerateViewConfigurations(XrInstance instance, XrSystemId system,
                                                           uint32_t capacity, uint32_t* count,
                                                           XrViewConfigurationType* types) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  const std::vector<XrViewConfigurationType> items{XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
  return enumerate(capacity, count, types, items,
                   [](XrViewConfigurationType& out, XrViewConfigurationType t) { out = t; });
}

XRAPI_ATTR XrResult XRAPI_CALL
getViewConfigurationProperties(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                               XrViewConfigurationProperties* properties) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  properties->viewConfigurationType = type;
  properties->fovMutable = XR_FALSE;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL enumerateViewConfigurationViews(XrInstance instance,
                                                               XrSystemId system,
                                                               XrViewConfigurationType type,
                                                               uint32_t capacity, uint32_t* count,
                                                               XrViewConfigurationView* views) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  const RuntimeConfig& c = in->config;
  return enumerate(capacity, count, views, c.views,
                   [&](XrViewConfigurationView& out, const parallax::xr_test::ViewConfig&) {
                     out.recommendedImageRectWidth = c.width;
                     out.maxImageRectWidth = 16384;
                     out.recommendedImageRectHeight = c.height;
                     out.maxImageRectHeight = 16384;
                     out.recommendedSwapchainSampleCount = 1;
                     out.maxSwapchainSampleCount = 1;
                   });
}

XRAPI_ATTR XrResult XRAPI_CALL getOpenGLGraphicsRequirements(
    XrInstance instance, XrSystemId system, XrGraphicsRequirementsOpenGLKHR* requirements) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  requirements->minApiVersionSupported = XR_MAKE_VERSION(4, 3, 0);
  requirements->maxApiVersionSupported = XR_MAKE_VERSION(4, 6, 0);
  return XR_SUCCESS;
}

// --- session -------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL createSession(XrInstance instance, const XrSessionCreateInfo* info,
                                             XrSession* session) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (info->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
  if (in->session) return XR_ERROR_LIMIT_REACHED;
  Binding binding = Binding::None;
  for (auto* s = static_cast<const XrBaseInStructure*>(info->next); s; s = s->next) {
    if (s->type == XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR) binding = Binding::OpenGlXlib;
    if (s->type == XR_TYPE_GRAPHICS_BINDING_EGL_MNDX) binding = Binding::Egl;
  }
  if (binding == Binding::None) return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  // Swapchain textures are made and read with GL calls in the application's context, which must
  // be current on this thread (epoxy resolves them through EGL or GLX, whichever made it current).
  if (epoxy_gl_version() < 43) return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  in->session = std::make_unique<Session>();
  in->session->binding = binding;
  *session = reinterpret_cast<XrSession>(in->session.get());
  pushState(*in->session, XR_SESSION_STATE_IDLE);
  pushState(*in->session, XR_SESSION_STATE_READY);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL destroySession(XrSession session) {
  if (!sessionOf(session)) return XR_ERROR_HANDLE_INVALID;
  g_instance->session.reset();
  // Events of the destroyed session are dropped: their handle means nothing now.
  g_instance->events.clear();
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL beginSession(XrSession handle, const XrSessionBeginInfo* info) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (s->running) return XR_ERROR_SESSION_RUNNING;
  if (s->state != XR_SESSION_STATE_READY) return XR_ERROR_SESSION_NOT_READY;
  if (info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  s->running = true;
  pushState(*s, XR_SESSION_STATE_SYNCHRONIZED);
  pushState(*s, XR_SESSION_STATE_VISIBLE);
  pushState(*s, XR_SESSION_STATE_FOCUSED);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL endSession(XrSession handle) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (s->state != XR_SESSION_STATE_STOPPING) return XR_ERROR_SESSION_NOT_STOPPING;
  s->running = false;
  pushState(*s, XR_SESSION_STATE_IDLE);
  pushState(*s, XR_SESSION_STATE_EXITING);
  return XR_SUCCESS;
}

// The runtime's side of ending a session: focus lost, then hidden, then stopping.
void stopSession(Session& s) {
  if (s.state == XR_SESSION_STATE_FOCUSED) pushState(s, XR_SESSION_STATE_VISIBLE);
  if (s.state == XR_SESSION_STATE_VISIBLE) pushState(s, XR_SESSION_STATE_SYNCHRONIZED);
  if (s.state == XR_SESSION_STATE_SYNCHRONIZED) pushState(s, XR_SESSION_STATE_STOPPING);
}

XRAPI_ATTR XrResult XRAPI_CALL requestExitSession(XrSession handle) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
  s->exit_requested = true;
  stopSession(*s);
  return XR_SUCCESS;
}

// --- spaces --------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL enumerateReferenceSpaces(XrSession handle, uint32_t capacity,
                                                        uint32_t* count,
                                                        XrReferenceSpaceType* types) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  const std::vector<XrReferenceSpaceType> items{
      XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL, XR_REFERENCE_SPACE_TYPE_STAGE};
  return enumerate(capacity, count, types, items,
                   [](XrReferenceSpaceType& out, XrReferenceSpaceType t) { out = t; });
}

XRAPI_ATTR XrResult XRAPI_CALL createReferenceSpace(XrSession handle,
                                                    const XrReferenceSpaceCreateInfo* info,
                                                    XrSpace* space) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  if (info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_VIEW &&
      info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_LOCAL &&
      info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_STAGE) {
    return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
  }
  auto* s = new Space{info->referenceSpaceType, nullptr, XR_NULL_PATH,
                      toPose(info->poseInReferenceSpace)};
  *space = reinterpret_cast<XrSpace>(s);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL getReferenceSpaceBoundsRect(XrSession handle, XrReferenceSpaceType,
                                                           XrExtent2Df* bounds) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  bounds->width = 0;
  bounds->height = 0;
  return XR_SPACE_BOUNDS_UNAVAILABLE;
}

XRAPI_ATTR XrResult XRAPI_CALL createActionSpace(XrSession handle,
                                                 const XrActionSpaceCreateInfo* info,
                                                 XrSpace* space) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  auto* action = reinterpret_cast<const Action*>(info->action);
  if (!action) return XR_ERROR_HANDLE_INVALID;
  if (action->type != XR_ACTION_TYPE_POSE_INPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
  auto* s = new Space{XR_REFERENCE_SPACE_TYPE_STAGE, action, info->subactionPath,
                      toPose(info->poseInActionSpace)};
  *space = reinterpret_cast<XrSpace>(s);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL destroySpace(XrSpace space) {
  delete reinterpret_cast<Space*>(space);
  return XR_SUCCESS;
}

// The head: between the eyes, turned as the left eye is.
Pose headPose(const RuntimeConfig& c) {
  const auto& l = c.views[0];
  const auto& r = c.views[1];
  Pose head;
  head.orientation =
      glm::quat(l.orientation[3], l.orientation[0], l.orientation[1], l.orientation[2]);
  head.position = 0.5f * (glm::vec3(l.position[0], l.position[1], l.position[2]) +
                          glm::vec3(r.position[0], r.position[1], r.position[2]));
  return head;
}

// A reference space's origin in stage space (LOCAL is the stage's origin here: the test headset
// never moves, so there is no recentring).
Pose spaceInStage(const Space& space) {
  const Pose base =
      space.type == XR_REFERENCE_SPACE_TYPE_VIEW ? headPose(g_instance->config) : Pose{};
  return compose(base, space.pose);
}

// The hand (0 left, 1 right) a subaction path names; -1 for XR_NULL_PATH or another path.
int handOf(XrPath path) {
  if (path == XR_NULL_PATH || path >= g_instance->paths.size()) return -1;
  const std::string& p = g_instance->paths[path];
  return p == "/user/hand/left" ? 0 : p == "/user/hand/right" ? 1 : -1;
}

// Where the configured profile binds `action` for `hand`: the input's path under
// /user/hand/<hand>/input/ ("trigger/value", "grip/pose"), or empty when it is not bound there.
std::string boundInput(const Action* action, int hand) {
  const Instance& in = *g_instance;
  const std::string& profile = in.config.controllers.profile;
  const std::string prefix =
      std::string("/user/hand/") + (hand == 0 ? "left" : "right") + "/input/";
  for (const auto& [profile_path, bindings] : in.suggested) {
    if (in.paths[profile_path] != profile) continue;
    for (const auto& [bound, input] : bindings) {
      if (bound == action && in.paths[input].rfind(prefix, 0) == 0) {
        return in.paths[input].substr(prefix.size());
      }
    }
  }
  return {};
}

// An action space's pose in the stage this frame; false where its hand is not tracked or the
// action not bound to one of its poses.
bool handPose(const Space& space, Pose& in_stage) {
  const Session* session = g_instance->session.get();
  if (!session || !session->controllers) return false;
  const int only = handOf(space.subaction);
  for (int h = 0; h < 2; ++h) {
    if (only >= 0 && h != only) continue;
    const auto& hand = session->controllers->hands[h];
    const std::string input = boundInput(space.action, h);
    if (!hand.tracked || (input != "grip/pose" && input != "aim/pose")) continue;
    const auto& p = input == "grip/pose" ? hand.grip : hand.aim;
    Pose pose;
    pose.orientation = glm::normalize(
        glm::quat(p.orientation[3], p.orientation[0], p.orientation[1], p.orientation[2]));
    pose.position = glm::vec3(p.position[0], p.position[1], p.position[2]);
    in_stage = compose(pose, space.pose);
    return true;
  }
  return false;
}

XRAPI_ATTR XrResult XRAPI_CALL locateSpace(XrSpace space, XrSpace base, XrTime,
                                           XrSpaceLocation* location) {
  const auto* s = reinterpret_cast<const Space*>(space);
  const auto* b = reinterpret_cast<const Space*>(base);
  if (!g_instance || !s || !b) return XR_ERROR_HANDLE_INVALID;
  Pose in_stage = spaceInStage(*s);
  if (b->action || (s->action && !handPose(*s, in_stage))) {
    location->locationFlags = 0;
    location->pose = toXr(Pose{});
    return XR_SUCCESS;
  }
  location->pose = toXr(compose(inverse(spaceInStage(*b)), in_stage));
  location->locationFlags =
      XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
      XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL locateViews(XrSession handle, const XrViewLocateInfo* info,
                                           XrViewState* state, uint32_t capacity, uint32_t* count,
                                           XrView* views) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  if (info->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  const auto* space = reinterpret_cast<const Space*>(info->space);
  if (!space || space->action) return XR_ERROR_HANDLE_INVALID;
  const Pose to_space = inverse(spaceInStage(*space));
  state->viewStateFlags = XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                          XR_VIEW_STATE_ORIENTATION_TRACKED_BIT |
                          XR_VIEW_STATE_POSITION_TRACKED_BIT;
  return enumerate(capacity, count, views, g_instance->config.views,
                   [&](XrView& out, const parallax::xr_test::ViewConfig& v) {
                     Pose eye;
                     eye.orientation = glm::quat(v.orientation[3], v.orientation[0],
                                                 v.orientation[1], v.orientation[2]);
                     eye.position = glm::vec3(v.position[0], v.position[1], v.position[2]);
                     out.pose = toXr(compose(to_space, eye));
                     out.fov = {v.fov_left, v.fov_right, v.fov_up, v.fov_down};
                   });
}

// --- swapchains ----------------------------------------------------------------------------------

const std::vector<int64_t> kColorFormats{GL_RGBA8, GL_SRGB8_ALPHA8};
const std::vector<int64_t> kDepthFormats{GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT24};

XRAPI_ATTR XrResult XRAPI_CALL enumerateSwapchainFormats(XrSession handle, uint32_t capacity,
                                                         uint32_t* count, int64_t* formats) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  std::vector<int64_t> items = kColorFormats;
  items.insert(items.end(), kDepthFormats.begin(), kDepthFormats.end());
  return enumerate(capacity, count, formats, items, [](int64_t& out, int64_t f) { out = f; });
}

XRAPI_ATTR XrResult XRAPI_CALL createSwapchain(XrSession handle, const XrSwapchainCreateInfo* info,
                                               XrSwapchain* swapchain) {
  const Session* session = sessionOf(handle);
  if (!session) return XR_ERROR_HANDLE_INVALID;
  const bool color =
      std::find(kColorFormats.begin(), kColorFormats.end(), info->format) != kColorFormats.end();
  const bool depth =
      std::find(kDepthFormats.begin(), kDepthFormats.end(), info->format) != kDepthFormats.end();
  if (!color && !depth) return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
  if (info->sampleCount != 1 || info->faceCount != 1 || info->mipCount != 1 || info->width == 0 ||
      info->height == 0 || info->arraySize == 0) {
    return XR_ERROR_FEATURE_UNSUPPORTED;
  }
  auto chain = std::make_unique<Swapchain>();
  chain->binding = session->binding;
  chain->width = info->width;
  chain->height = info->height;
  chain->array_size = info->arraySize;
  chain->format = info->format;
  chain->textures.resize(kSwapchainImages);
  const GLenum target = info->arraySize > 1 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
  glCreateTextures(target, kSwapchainImages, chain->textures.data());
  for (GLuint texture : chain->textures) {
    if (info->arraySize > 1) {
      glTextureStorage3D(texture, 1, GLenum(info->format), GLsizei(info->width),
                         GLsizei(info->height), GLsizei(info->arraySize));
    } else {
      glTextureStorage2D(texture, 1, GLenum(info->format), GLsizei(info->width),
                         GLsizei(info->height));
    }
  }
  if (glGetError() != GL_NO_ERROR) {
    glDeleteTextures(kSwapchainImages, chain->textures.data());
    return XR_ERROR_RUNTIME_FAILURE;
  }
  *swapchain = reinterpret_cast<XrSwapchain>(chain.release());
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL destroySwapchain(XrSwapchain handle) {
  auto* chain = reinterpret_cast<Swapchain*>(handle);
  if (!chain) return XR_ERROR_HANDLE_INVALID;
  // The application's context may already be gone (it destroys its swapchains at the end).
  if (chain->binding != Binding::Egl || eglGetCurrentContext() != EGL_NO_CONTEXT) {
    glDeleteTextures(kSwapchainImages, chain->textures.data());
  }
  delete chain;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL enumerateSwapchainImages(XrSwapchain handle, uint32_t capacity,
                                                        uint32_t* count,
                                                        XrSwapchainImageBaseHeader* images) {
  auto* chain = reinterpret_cast<Swapchain*>(handle);
  if (!chain) return XR_ERROR_HANDLE_INVALID;
  auto* gl_images = reinterpret_cast<XrSwapchainImageOpenGLKHR*>(images);
  return enumerate(capacity, count, gl_images, chain->textures,
                   [](XrSwapchainImageOpenGLKHR& out, GLuint texture) { out.image = texture; });
}

XRAPI_ATTR XrResult XRAPI_CALL acquireSwapchainImage(XrSwapchain handle,
                                                     const XrSwapchainImageAcquireInfo*,
                                                     uint32_t* index) {
  auto* chain = reinterpret_cast<Swapchain*>(handle);
  if (!chain) return XR_ERROR_HANDLE_INVALID;
  if (chain->acquired == kSwapchainImages) return XR_ERROR_CALL_ORDER_INVALID;
  *index = chain->next;
  chain->next = (chain->next + 1) % kSwapchainImages;
  ++chain->acquired;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL waitSwapchainImage(XrSwapchain handle,
                                                  const XrSwapchainImageWaitInfo*) {
  return handle ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}

XRAPI_ATTR XrResult XRAPI_CALL releaseSwapchainImage(XrSwapchain handle,
                                                     const XrSwapchainImageReleaseInfo*) {
  auto* chain = reinterpret_cast<Swapchain*>(handle);
  if (!chain) return XR_ERROR_HANDLE_INVALID;
  if (chain->acquired == 0) return XR_ERROR_CALL_ORDER_INVALID;
  // Images are released in the order they were acquired.
  chain->released = int((chain->next + kSwapchainImages - chain->acquired) % kSwapchainImages);
  --chain->acquired;
  return XR_SUCCESS;
}

// --- frames --------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL waitFrame(XrSession handle, const XrFrameWaitInfo*,
                                         XrFrameState* state) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
  ++s->frames_waited;
  // Paced as a real compositor paces its application: xrWaitFrame blocks until the last predicted
  // display time, so frames come at most once a display period (an application that draws
  // faster waits; one that draws slower misses displays). Tests that count on time passing
  // between frames (loads arriving meanwhile) get what a headset gives them.
  const XrTime wait_until = s->last_display_time;
  if (now(*s) < wait_until) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(wait_until - now(*s)));
  }
  state->predictedDisplayPeriod = kFramePeriod;
  state->predictedDisplayTime = now(*s) + kFramePeriod;
  s->last_display_time = state->predictedDisplayTime;
  state->shouldRender = s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED
                            ? XR_TRUE
                            : XR_FALSE;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL beginFrame(XrSession handle, const XrFrameBeginInfo*) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
  const bool discarded = s->frame_begun;
  s->frame_begun = true;
  return discarded ? XR_FRAME_DISCARDED : XR_SUCCESS;
}

nlohmann::json poseJson(const XrPosef& p) {
  return {{"position", {p.position.x, p.position.y, p.position.z}},
          {"orientation", {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w}}};
}

// Writes one submitted projection view as a PNG (top row first); false when it cannot be read.
bool writeView(const XrCompositionLayerProjectionView& view, const std::filesystem::path& png) {
  const auto* chain = reinterpret_cast<const Swapchain*>(view.subImage.swapchain);
  if (!chain || chain->released < 0) return false;
  const XrRect2Di& r = view.subImage.imageRect;
  if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
      uint32_t(r.offset.x + r.extent.width) > chain->width ||
      uint32_t(r.offset.y + r.extent.height) > chain->height) {
    return false;
  }
  const int w = r.extent.width, h = r.extent.height;
  std::vector<unsigned char> rows(std::size_t(w) * h * 4), flipped(rows.size());
  glGetTextureSubImage(chain->textures[std::size_t(chain->released)], 0, r.offset.x, r.offset.y,
                       GLint(view.subImage.imageArrayIndex), w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                       GLsizei(rows.size()), rows.data());
  if (glGetError() != GL_NO_ERROR) return false;
  // GL's rows start at the bottom (the image rect's offset is from the texture's first row).
  for (int y = 0; y < h; ++y) {
    std::memcpy(&flipped[std::size_t(y) * w * 4], &rows[std::size_t(h - 1 - y) * w * 4],
                std::size_t(w) * 4);
  }
  return stbi_write_png(png.c_str(), w, h, 4, flipped.data(), w * 4) != 0;
}

XRAPI_ATTR XrResult XRAPI_CALL endFrame(XrSession handle, const XrFrameEndInfo* info) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (!s->frame_begun) return XR_ERROR_CALL_ORDER_INVALID;
  s->frame_begun = false;
  const RuntimeConfig& c = g_instance->config;
  const uint64_t frame = s->frames_ended++;
  if (!c.output.empty()) {
    nlohmann::json doc = {
        {"frame", frame}, {"display_time", info->displayTime}, {"layers", nlohmann::json::array()}};
    int written = 0;
    for (uint32_t l = 0; l < info->layerCount; ++l) {
      const XrCompositionLayerBaseHeader* layer = info->layers[l];
      if (layer->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) continue;
      const auto* projection = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
      nlohmann::json views = nlohmann::json::array();
      for (uint32_t v = 0; v < projection->viewCount; ++v) {
        const XrCompositionLayerProjectionView& view = projection->views[v];
        const auto png = std::filesystem::path(c.output) /
                         ("frame_" + std::to_string(frame) + "_view_" + std::to_string(v) + ".png");
        std::error_code ec;
        std::filesystem::create_directories(c.output, ec);
        if (!writeView(view, png)) {
          std::fprintf(stderr, "Parallax test runtime: cannot write %s\n", png.c_str());
          return XR_ERROR_RUNTIME_FAILURE;
        }
        ++written;
        const XrRect2Di& r = view.subImage.imageRect;
        views.push_back({{"pose", poseJson(view.pose)},
                         {"fov",
                          {{"left", view.fov.angleLeft},
                           {"right", view.fov.angleRight},
                           {"up", view.fov.angleUp},
                           {"down", view.fov.angleDown}}},
                         {"image_rect",
                          {{"x", r.offset.x},
                           {"y", r.offset.y},
                           {"width", r.extent.width},
                           {"height", r.extent.height}}},
                         {"image_array_index", view.subImage.imageArrayIndex}});
      }
      doc["layers"].push_back({{"views", views}});
    }
    (void)written;
    std::ofstream out(std::filesystem::path(c.output) /
                      ("frame_" + std::to_string(frame) + ".json"));
    out << doc.dump(2) << '\n';
  }
  if (s->frames_ended >= c.frames) stopSession(*s);
  return XR_SUCCESS;
}

// --- actions (scripted by the configuration's "controllers") ----------------------------------

// Every interaction profile of the OpenXR 1.0 specification (section 6.4): a runtime accepts
// suggested bindings for all of them (hello_xr suggests Vive and Windows Mixed Reality bindings
// too), and the configuration's profile, one of the first three, is the one it reports.
const char* const kProfiles[] = {"/interaction_profiles/khr/simple_controller",
                                 "/interaction_profiles/oculus/touch_controller",
                                 "/interaction_profiles/valve/index_controller",
                                 "/interaction_profiles/google/daydream_controller",
                                 "/interaction_profiles/htc/vive_controller",
                                 "/interaction_profiles/htc/vive_pro",
                                 "/interaction_profiles/microsoft/motion_controller",
                                 "/interaction_profiles/microsoft/xbox_controller",
                                 "/interaction_profiles/oculus/go_controller"};

XRAPI_ATTR XrResult XRAPI_CALL createActionSet(XrInstance instance,
                                               const XrActionSetCreateInfo* info,
                                               XrActionSet* set) {
  if (!instanceOf(instance)) return XR_ERROR_HANDLE_INVALID;
  *set = reinterpret_cast<XrActionSet>(new ActionSet{info->actionSetName, false});
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL destroyActionSet(XrActionSet set) {
  delete reinterpret_cast<ActionSet*>(set);
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL createAction(XrActionSet set, const XrActionCreateInfo* info,
                                            XrAction* action) {
  if (!set) return XR_ERROR_HANDLE_INVALID;
  if (reinterpret_cast<ActionSet*>(set)->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
  *action = reinterpret_cast<XrAction>(new Action{info->actionType, info->actionName});
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL destroyAction(XrAction action) {
  delete reinterpret_cast<Action*>(action);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL suggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* suggested) {
  Instance* in = instanceOf(instance);
  if (!in) return XR_ERROR_HANDLE_INVALID;
  if (suggested->interactionProfile >= in->paths.size()) return XR_ERROR_PATH_INVALID;
  const std::string& profile = in->paths[suggested->interactionProfile];
  bool known = false;
  for (const char* p : kProfiles) known |= profile == p;
  if (!known) return XR_ERROR_PATH_UNSUPPORTED;
  std::vector<std::pair<const Action*, XrPath>> bindings;
  for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
    const XrPath path = suggested->suggestedBindings[i].binding;
    if (path >= in->paths.size() || in->paths[path].rfind("/user/hand/", 0) != 0) {
      return XR_ERROR_PATH_UNSUPPORTED;
    }
    bindings.emplace_back(reinterpret_cast<const Action*>(suggested->suggestedBindings[i].action),
                          path);
  }
  // A later suggestion for the same profile replaces the earlier one (specification).
  in->suggested[suggested->interactionProfile] = std::move(bindings);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL attachSessionActionSets(XrSession handle,
                                                       const XrSessionActionSetsAttachInfo* info) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (s->actions_attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
  for (uint32_t i = 0; i < info->countActionSets; ++i) {
    auto* set = reinterpret_cast<ActionSet*>(info->actionSets[i]);
    if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    set->attached = true;
  }
  s->actions_attached = true;
  if (!g_instance->config.controllers.profile.empty()) {
    // The controllers are "connected" now: the application learns their profile from this event.
    XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER};
    auto* changed = reinterpret_cast<XrEventDataInteractionProfileChanged*>(&buffer);
    changed->type = XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
    changed->next = nullptr;
    changed->session = handle;
    g_instance->events.push_back(buffer);
  }
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL getCurrentInteractionProfile(XrSession handle, XrPath top_level,
                                                            XrInteractionProfileState* state) {
  const Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->actions_attached) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  state->interactionProfile = XR_NULL_PATH;
  if (handOf(top_level) < 0) return XR_SUCCESS;
  for (const auto& [profile, bindings] : g_instance->suggested) {
    if (g_instance->paths[profile] == g_instance->config.controllers.profile) {
      state->interactionProfile = profile;
    }
  }
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL syncActions(XrSession handle, const XrActionsSyncInfo*) {
  Session* s = sessionOf(handle);
  if (!s) return XR_ERROR_HANDLE_INVALID;
  if (!s->actions_attached) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  if (s->state != XR_SESSION_STATE_FOCUSED) {
    s->controllers = nullptr;
    return XR_SESSION_NOT_FOCUSED;
  }
  // The frame being drawn: xrEndFrame has been called frames_ended times.
  s->controllers = g_instance->config.controllers.at(s->frames_ended);
  return XR_SUCCESS;
}

// An action's state for the hands the request names: active where a tracked hand has the action
// bound; its value the bound input's (0 where the entry does not list it), the largest of the
// two hands' where the request names none.
struct ActionValue {
  bool active = false;
  std::array<float, 2> value{0, 0};
};
ActionValue actionValue(const XrActionStateGetInfo* info) {
  ActionValue out;
  const Session* s = g_instance->session.get();
  const auto* action = reinterpret_cast<const Action*>(info->action);
  if (!s || !s->controllers || !action) return out;
  const int only = handOf(info->subactionPath);
  for (int h = 0; h < 2; ++h) {
    if (only >= 0 && h != only) continue;
    const auto& hand = s->controllers->hands[h];
    const std::string input = boundInput(action, h);
    if (!hand.tracked || input.empty()) continue;
    out.active = true;
    const auto it = hand.inputs.find(input);
    const std::array<float, 2> v =
        it == hand.inputs.end() ? std::array<float, 2>{0, 0} : it->second;
    if (std::hypot(v[0], v[1]) > std::hypot(out.value[0], out.value[1])) out.value = v;
  }
  return out;
}

XRAPI_ATTR XrResult XRAPI_CALL getActionStateBoolean(XrSession handle,
                                                     const XrActionStateGetInfo* info,
                                                     XrActionStateBoolean* state) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  const ActionValue v = actionValue(info);
  state->currentState = v.value[0] > 0.5f ? XR_TRUE : XR_FALSE;
  state->changedSinceLastSync = XR_FALSE;
  state->lastChangeTime = 0;
  state->isActive = v.active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL getActionStateFloat(XrSession handle,
                                                   const XrActionStateGetInfo* info,
                                                   XrActionStateFloat* state) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  const ActionValue v = actionValue(info);
  state->currentState = v.value[0];
  state->changedSinceLastSync = XR_FALSE;
  state->lastChangeTime = 0;
  state->isActive = v.active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL getActionStateVector2f(XrSession handle,
                                                      const XrActionStateGetInfo* info,
                                                      XrActionStateVector2f* state) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  const ActionValue v = actionValue(info);
  state->currentState = {v.value[0], v.value[1]};
  state->changedSinceLastSync = XR_FALSE;
  state->lastChangeTime = 0;
  state->isActive = v.active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL getActionStatePose(XrSession handle,
                                                  const XrActionStateGetInfo* info,
                                                  XrActionStatePose* state) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  state->isActive = actionValue(info).active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL
enumerateBoundSourcesForAction(XrSession handle, const XrBoundSourcesForActionEnumerateInfo*,
                               uint32_t capacity, uint32_t* count, XrPath* sources) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  return enumerate(capacity, count, sources, std::vector<XrPath>{},
                   [](XrPath& out, XrPath p) { out = p; });
}
XRAPI_ATTR XrResult XRAPI_CALL getInputSourceLocalizedName(XrSession handle,
                                                           const XrInputSourceLocalizedNameGetInfo*,
                                                           uint32_t capacity, uint32_t* count,
                                                           char* buffer) {
  if (!sessionOf(handle)) return XR_ERROR_HANDLE_INVALID;
  *count = 1;
  if (capacity > 0) buffer[0] = '\0';
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL applyHapticFeedback(XrSession handle, const XrHapticActionInfo*,
                                                   const XrHapticBaseHeader*) {
  return sessionOf(handle) ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}
XRAPI_ATTR XrResult XRAPI_CALL stopHapticFeedback(XrSession handle, const XrHapticActionInfo*) {
  return sessionOf(handle) ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}

// --- dispatch ------------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL getInstanceProcAddr(XrInstance instance, const char* name,
                                                   PFN_xrVoidFunction* function);

const std::map<std::string, PFN_xrVoidFunction>& functions() {
#define PARALLAX_XR_FN(api, impl) \
  { #api, reinterpret_cast < PFN_xrVoidFunction>(&impl) }
  static const std::map<std::string, PFN_xrVoidFunction> table{
      PARALLAX_XR_FN(xrGetInstanceProcAddr, getInstanceProcAddr),
      PARALLAX_XR_FN(xrEnumerateInstanceExtensionProperties, enumerateInstanceExtensionProperties),
      PARALLAX_XR_FN(xrCreateInstance, createInstance),
      PARALLAX_XR_FN(xrDestroyInstance, destroyInstance),
      PARALLAX_XR_FN(xrGetInstanceProperties, getInstanceProperties),
      PARALLAX_XR_FN(xrPollEvent, pollEvent),
      PARALLAX_XR_FN(xrResultToString, resultToString),
      PARALLAX_XR_FN(xrStructureTypeToString, structureTypeToString),
      PARALLAX_XR_FN(xrStringToPath, stringToPath),
      PARALLAX_XR_FN(xrPathToString, pathToString),
      PARALLAX_XR_FN(xrGetSystem, getSystem),
      PARALLAX_XR_FN(xrGetSystemProperties, getSystemProperties),
      PARALLAX_XR_FN(xrEnumerateEnvironmentBlendModes, enumerateEnvironmentBlendModes),
      PARALLAX_XR_FN(xrEnumerateViewConfigurations, enumerateViewConfigurations),
      PARALLAX_XR_FN(xrGetViewConfigurationProperties, getViewConfigurationProperties),
      PARALLAX_XR_FN(xrEnumerateViewConfigurationViews, enumerateViewConfigurationViews),
      PARALLAX_XR_FN(xrGetOpenGLGraphicsRequirementsKHR, getOpenGLGraphicsRequirements),
      PARALLAX_XR_FN(xrCreateSession, createSession),
      PARALLAX_XR_FN(xrDestroySession, destroySession),
      PARALLAX_XR_FN(xrBeginSession, beginSession),
      PARALLAX_XR_FN(xrEndSession, endSession),
      PARALLAX_XR_FN(xrRequestExitSession, requestExitSession),
      PARALLAX_XR_FN(xrEnumerateReferenceSpaces, enumerateReferenceSpaces),
      PARALLAX_XR_FN(xrCreateReferenceSpace, createReferenceSpace),
      PARALLAX_XR_FN(xrGetReferenceSpaceBoundsRect, getReferenceSpaceBoundsRect),
      PARALLAX_XR_FN(xrCreateActionSpace, createActionSpace),
      PARALLAX_XR_FN(xrLocateSpace, locateSpace),
      PARALLAX_XR_FN(xrDestroySpace, destroySpace),
      PARALLAX_XR_FN(xrLocateViews, locateViews),
      PARALLAX_XR_FN(xrEnumerateSwapchainFormats, enumerateSwapchainFormats),
      PARALLAX_XR_FN(xrCreateSwapchain, createSwapchain),
      PARALLAX_XR_FN(xrDestroySwapchain, destroySwapchain),
      PARALLAX_XR_FN(xrEnumerateSwapchainImages, enumerateSwapchainImages),
      PARALLAX_XR_FN(xrAcquireSwapchainImage, acquireSwapchainImage),
      PARALLAX_XR_FN(xrWaitSwapchainImage, waitSwapchainImage),
      PARALLAX_XR_FN(xrReleaseSwapchainImage, releaseSwapchainImage),
      PARALLAX_XR_FN(xrWaitFrame, waitFrame),
      PARALLAX_XR_FN(xrBeginFrame, beginFrame),
      PARALLAX_XR_FN(xrEndFrame, endFrame),
      PARALLAX_XR_FN(xrCreateActionSet, createActionSet),
      PARALLAX_XR_FN(xrDestroyActionSet, destroyActionSet),
      PARALLAX_XR_FN(xrCreateAction, createAction),
      PARALLAX_XR_FN(xrDestroyAction, destroyAction),
      PARALLAX_XR_FN(xrSuggestInteractionProfileBindings, suggestInteractionProfileBindings),
      PARALLAX_XR_FN(xrAttachSessionActionSets, attachSessionActionSets),
      PARALLAX_XR_FN(xrGetCurrentInteractionProfile, getCurrentInteractionProfile),
      PARALLAX_XR_FN(xrSyncActions, syncActions),
      PARALLAX_XR_FN(xrGetActionStateBoolean, getActionStateBoolean),
      PARALLAX_XR_FN(xrGetActionStateFloat, getActionStateFloat),
      PARALLAX_XR_FN(xrGetActionStateVector2f, getActionStateVector2f),
      PARALLAX_XR_FN(xrGetActionStatePose, getActionStatePose),
      PARALLAX_XR_FN(xrEnumerateBoundSourcesForAction, enumerateBoundSourcesForAction),
      PARALLAX_XR_FN(xrGetInputSourceLocalizedName, getInputSourceLocalizedName),
      PARALLAX_XR_FN(xrApplyHapticFeedback, applyHapticFeedback),
      PARALLAX_XR_FN(xrStopHapticFeedback, stopHapticFeedback),
  };
#undef PARALLAX_XR_FN
  return table;
}

XRAPI_ATTR XrResult XRAPI_CALL getInstanceProcAddr(XrInstance instance, const char* name,
                                                   PFN_xrVoidFunction* function) {
  *function = nullptr;
  const std::string n = name;
  // Without an instance, only the functions that make one (specification, xrGetInstanceProcAddr).
  if (instance == XR_NULL_HANDLE && n != "xrEnumerateInstanceExtensionProperties" &&
      n != "xrCreateInstance" && n != "xrEnumerateApiLayerProperties" &&
      n != "xrGetInstanceProcAddr") {
    return XR_ERROR_HANDLE_INVALID;
  }
  const auto it = functions().find(n);
  if (it == functions().end()) return XR_ERROR_FUNCTION_UNSUPPORTED;
  *function = it->second;
  return XR_SUCCESS;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) XrResult xrNegotiateLoaderRuntimeInterface(
    const XrNegotiateLoaderInfo* loader, XrNegotiateRuntimeRequest* request) {
  if (loader == nullptr || request == nullptr ||
      loader->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
      loader->structVersion != kLoaderInfoStructVersion ||
      loader->structSize != sizeof(XrNegotiateLoaderInfo) ||
      request->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
      request->structVersion != kRuntimeInfoStructVersion ||
      request->structSize != sizeof(XrNegotiateRuntimeRequest) ||
      loader->minInterfaceVersion > kLoaderRuntimeVersion ||
      loader->maxInterfaceVersion < kLoaderRuntimeVersion ||
      loader->minApiVersion > XR_CURRENT_API_VERSION) {
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  request->runtimeInterfaceVersion = kLoaderRuntimeVersion;
  request->runtimeApiVersion = XR_CURRENT_API_VERSION;
  request->getInstanceProcAddr = &getInstanceProcAddr;
  return XR_SUCCESS;
}
