#include "xr/xr_headset.h"

#include <epoxy/egl.h>
#include <epoxy/glx.h>
#define XR_USE_GRAPHICS_API_OPENGL
#define XR_USE_PLATFORM_EGL
#define XR_USE_PLATFORM_XLIB
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "xr/xr_actions.h"

namespace parallax {
namespace {

std::string resultName(XrInstance instance, XrResult result) {
  char buffer[XR_MAX_RESULT_STRING_SIZE] = {};
  if (instance != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance, result, buffer))) {
    return buffer;
  }
  return "XrResult " + std::to_string(int(result));
}

}  // namespace

void xrCheck(XrInstance instance, XrResult result, const char* call) {
  if (XR_FAILED(result)) {
    throw XrError(std::string("OpenXR: ") + call + " failed: " + resultName(instance, result) +
                  " (runtime: " + xrRuntimeLookedFor() + ")");
  }
}

std::string xrRuntimeLookedFor() {
  if (const char* json = std::getenv("XR_RUNTIME_JSON"); json && *json) {
    return std::string("XR_RUNTIME_JSON=") + json;
  }
  std::string home_config;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) {
    home_config = xdg;
  } else if (const char* home = std::getenv("HOME"); home && *home) {
    home_config = std::string(home) + "/.config";
  }
  std::string dirs = "/etc/xdg";
  if (const char* xdg_dirs = std::getenv("XDG_CONFIG_DIRS"); xdg_dirs && *xdg_dirs) dirs = xdg_dirs;
  std::string text = "the active runtime, openxr/1/active_runtime.json in ";
  if (!home_config.empty()) text += home_config + ", ";
  return text + dirs + " or /etc (set XR_RUNTIME_JSON to a runtime's manifest)";
}

struct XrHeadset::State {
  XrInstance instance = XR_NULL_HANDLE;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  XrSession session = XR_NULL_HANDLE;
  XrSpace space = XR_NULL_HANDLE;
  XrSwapchain swapchain = XR_NULL_HANDLE;
  std::vector<XrSwapchainImageOpenGLKHR> images;
  std::vector<XrViewConfigurationView> config_views;
  GLuint framebuffer = 0, depth = 0;
  int eye_width = 0, eye_height = 0;
  XrSessionState session_state = XR_SESSION_STATE_UNKNOWN;
  bool running = false;
  XrSessionStats stats;
  std::unique_ptr<XrActions> actions;
  XrInput input;

  void check(XrResult result, const char* call) const { xrCheck(instance, result, call); }
  // OpenXR's two-call idiom: the count first, then that many elements filled, each starting as
  // `blank` (typed structs need their type set before the runtime fills them).
  template <typename T, typename Call>
  std::vector<T> enumerate(const char* call_name, T blank, Call call) const {
    uint32_t count = 0;
    check(call(0u, &count, static_cast<T*>(nullptr)), call_name);
    std::vector<T> items(count, blank);
    check(call(count, &count, items.data()), call_name);
    items.resize(count);
    return items;
  }
};

XrHeadset::XrHeadset(const std::string& application_name) : state_(std::make_unique<State>()) {
  State& s = *state_;
  // The binding follows the context that is current: a headless EGL context needs the runtime's
  // XR_MNDX_egl_enable (and XR_KHR_opengl_enable, which it builds on); a window's GLX context
  // (the mirror) the Xlib binding of XR_KHR_opengl_enable alone, which every OpenGL runtime and
  // Debian's core validation layer know.
  const bool egl = eglGetCurrentContext() != EGL_NO_CONTEXT;
  if (!egl && glXGetCurrentContext() == nullptr) {
    throw XrError("OpenXR: no current EGL or GLX context to draw the headset's frames with");
  }
  uint32_t count = 0;
  XrResult result = xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr);
  if (XR_FAILED(result)) {
    throw XrError("no OpenXR runtime: " + resultName(XR_NULL_HANDLE, result) + "; looked for " +
                  xrRuntimeLookedFor());
  }
  std::vector<XrExtensionProperties> extensions(count, {XR_TYPE_EXTENSION_PROPERTIES});
  s.check(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, extensions.data()),
          "xrEnumerateInstanceExtensionProperties");
  bool has_gl = false, has_egl = false;
  for (const auto& e : extensions) {
    has_gl |= std::strcmp(e.extensionName, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME) == 0;
    has_egl |= std::strcmp(e.extensionName, XR_MNDX_EGL_ENABLE_EXTENSION_NAME) == 0;
  }
  if (!has_gl || (egl && !has_egl)) {
    throw XrError("OpenXR runtime (" + xrRuntimeLookedFor() + ") lacks " +
                  (has_gl ? "" : "XR_KHR_opengl_enable ") +
                  (egl && !has_egl ? "XR_MNDX_egl_enable " : "") +
                  (egl ? "which headless OpenGL drawing needs (a window, on a display, would "
                         "need only XR_KHR_opengl_enable)"
                       : "which OpenGL drawing needs"));
  }
  // XR_KHR_opengl_enable first: the GLX binding enables it alone.
  const char* enabled[] = {XR_KHR_OPENGL_ENABLE_EXTENSION_NAME, XR_MNDX_EGL_ENABLE_EXTENSION_NAME};
  XrInstanceCreateInfo create{XR_TYPE_INSTANCE_CREATE_INFO};
  std::snprintf(create.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "%s",
                application_name.c_str());
  std::snprintf(create.applicationInfo.engineName, XR_MAX_ENGINE_NAME_SIZE, "Parallax");
  create.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
  create.enabledExtensionCount = egl ? 2 : 1;
  create.enabledExtensionNames = enabled;
  result = xrCreateInstance(&create, &s.instance);
  if (XR_FAILED(result)) {
    throw XrError("no OpenXR runtime: xrCreateInstance failed: " +
                  resultName(XR_NULL_HANDLE, result) + "; looked for " + xrRuntimeLookedFor());
  }
  XrInstanceProperties properties{XR_TYPE_INSTANCE_PROPERTIES};
  s.check(xrGetInstanceProperties(s.instance, &properties), "xrGetInstanceProperties");
  s.stats.runtime = std::string(properties.runtimeName) + " " +
                    std::to_string(XR_VERSION_MAJOR(properties.runtimeVersion)) + "." +
                    std::to_string(XR_VERSION_MINOR(properties.runtimeVersion)) + "." +
                    std::to_string(XR_VERSION_PATCH(properties.runtimeVersion));

  XrSystemGetInfo system_info{XR_TYPE_SYSTEM_GET_INFO};
  system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  result = xrGetSystem(s.instance, &system_info, &s.system);
  if (XR_FAILED(result)) {
    const std::string why = resultName(s.instance, result);
    xrDestroyInstance(s.instance);
    throw XrError("no headset: xrGetSystem failed: " + why + " (runtime " + s.stats.runtime + ")");
  }
  XrSystemProperties system_properties{XR_TYPE_SYSTEM_PROPERTIES};
  s.check(xrGetSystemProperties(s.instance, s.system, &system_properties), "xrGetSystemProperties");
  s.stats.system = system_properties.systemName;

  s.config_views = s.enumerate(
      "xrEnumerateViewConfigurationViews", XrViewConfigurationView{XR_TYPE_VIEW_CONFIGURATION_VIEW},
      [&](uint32_t capacity, uint32_t* filled, XrViewConfigurationView* items) {
        return xrEnumerateViewConfigurationViews(s.instance, s.system,
                                                 XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                                                 capacity, filled, items);
      });
  const std::size_t views = s.config_views.size();
  if (views != 2)
    throw XrError("OpenXR: the stereo view configuration has " + std::to_string(views) +
                  " views, expected 2");
  s.eye_width = int(s.config_views[0].recommendedImageRectWidth);
  s.eye_height = int(s.config_views[0].recommendedImageRectHeight);
  s.stats.eye_width = s.eye_width;
  s.stats.eye_height = s.eye_height;

  // OpenXR requires the graphics requirements to be queried before the session is made.
  PFN_xrGetOpenGLGraphicsRequirementsKHR requirements_fn = nullptr;
  s.check(xrGetInstanceProcAddr(s.instance, "xrGetOpenGLGraphicsRequirementsKHR",
                                reinterpret_cast<PFN_xrVoidFunction*>(&requirements_fn)),
          "xrGetInstanceProcAddr(xrGetOpenGLGraphicsRequirementsKHR)");
  XrGraphicsRequirementsOpenGLKHR requirements{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
  s.check(requirements_fn(s.instance, s.system, &requirements),
          "xrGetOpenGLGraphicsRequirementsKHR");

  XrGraphicsBindingEGLMNDX egl_binding{XR_TYPE_GRAPHICS_BINDING_EGL_MNDX};
  XrGraphicsBindingOpenGLXlibKHR glx_binding{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
  XrSessionCreateInfo session_info{XR_TYPE_SESSION_CREATE_INFO};
  if (egl) {
    egl_binding.getProcAddress = eglGetProcAddress;
    egl_binding.display = eglGetCurrentDisplay();
    egl_binding.context = eglGetCurrentContext();
    EGLint config_id = 0;
    eglQueryContext(egl_binding.display, egl_binding.context, EGL_CONFIG_ID, &config_id);
    const EGLint attributes[] = {EGL_CONFIG_ID, config_id, EGL_NONE};
    EGLint configs = 0;
    egl_binding.config = nullptr;
    if (config_id > 0) {
      eglChooseConfig(egl_binding.display, attributes, &egl_binding.config, 1, &configs);
    }
    session_info.next = &egl_binding;
    s.stats.binding = "EGL (XR_MNDX_egl_enable)";
  } else {
    glx_binding.xDisplay = glXGetCurrentDisplay();
    glx_binding.glxContext = glXGetCurrentContext();
    glx_binding.glxDrawable = glXGetCurrentDrawable();
    // The context's framebuffer configuration and its visual, as the binding asks for them.
    int config_id = 0, screen = 0;
    glXQueryContext(glx_binding.xDisplay, glx_binding.glxContext, GLX_FBCONFIG_ID, &config_id);
    glXQueryContext(glx_binding.xDisplay, glx_binding.glxContext, GLX_SCREEN, &screen);
    const int attributes[] = {GLX_FBCONFIG_ID, config_id, 0};
    int configs = 0;
    GLXFBConfig* found = glXChooseFBConfig(glx_binding.xDisplay, screen, attributes, &configs);
    if (found && configs > 0) {
      glx_binding.glxFBConfig = found[0];
      int visual = 0;
      glXGetFBConfigAttrib(glx_binding.xDisplay, found[0], GLX_VISUAL_ID, &visual);
      glx_binding.visualid = uint32_t(visual);
    }
    if (found) XFree(found);
    session_info.next = &glx_binding;
    s.stats.binding = "GLX (XR_KHR_opengl_enable)";
  }
  session_info.systemId = s.system;
  s.check(xrCreateSession(s.instance, &session_info, &s.session), "xrCreateSession");

  const std::vector<XrReferenceSpaceType> spaces =
      s.enumerate("xrEnumerateReferenceSpaces", XrReferenceSpaceType{},
                  [&](uint32_t capacity, uint32_t* filled, XrReferenceSpaceType* items) {
                    return xrEnumerateReferenceSpaces(s.session, capacity, filled, items);
                  });
  XrReferenceSpaceCreateInfo space_info{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
  space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
  for (auto type : spaces) {
    if (type == XR_REFERENCE_SPACE_TYPE_STAGE) space_info.referenceSpaceType = type;
  }
  space_info.poseInReferenceSpace.orientation.w = 1.0f;
  s.check(xrCreateReferenceSpace(s.session, &space_info, &s.space), "xrCreateReferenceSpace");
  s.actions = std::make_unique<XrActions>(s.instance, s.session);

  const std::vector<int64_t> formats =
      s.enumerate("xrEnumerateSwapchainFormats", int64_t{},
                  [&](uint32_t capacity, uint32_t* filled, int64_t* items) {
                    return xrEnumerateSwapchainFormats(s.session, capacity, filled, items);
                  });
  // Linear RGBA8, as the renderer's pictures and PNGs are; sRGB where the runtime has nothing else.
  int64_t format = 0;
  for (int64_t f : formats) {
    if (f == GL_RGBA8 || (format == 0 && f == GL_SRGB8_ALPHA8)) format = f;
  }
  if (format == 0)
    throw XrError("OpenXR: the runtime offers no GL_RGBA8 or GL_SRGB8_ALPHA8 swapchain");
  XrSwapchainCreateInfo swapchain_info{XR_TYPE_SWAPCHAIN_CREATE_INFO};
  swapchain_info.usageFlags =
      XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
  swapchain_info.format = format;
  swapchain_info.sampleCount = 1;
  swapchain_info.width = uint32_t(2 * s.eye_width);
  swapchain_info.height = uint32_t(s.eye_height);
  swapchain_info.faceCount = 1;
  swapchain_info.arraySize = 1;
  swapchain_info.mipCount = 1;
  s.check(xrCreateSwapchain(s.session, &swapchain_info, &s.swapchain), "xrCreateSwapchain");
  s.images = s.enumerate(
      "xrEnumerateSwapchainImages", XrSwapchainImageOpenGLKHR{XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR},
      [&](uint32_t capacity, uint32_t* filled, XrSwapchainImageOpenGLKHR* items) {
        return xrEnumerateSwapchainImages(s.swapchain, capacity, filled,
                                          reinterpret_cast<XrSwapchainImageBaseHeader*>(items));
      });
  glCreateFramebuffers(1, &s.framebuffer);
}

XrHeadset::~XrHeadset() {
  State& s = *state_;
  if (s.framebuffer) glDeleteFramebuffers(1, &s.framebuffer);
  s.actions.reset();
  if (s.swapchain) xrDestroySwapchain(s.swapchain);
  if (s.space) xrDestroySpace(s.space);
  if (s.session) xrDestroySession(s.session);
  if (s.instance) xrDestroyInstance(s.instance);
}

int XrHeadset::eyeWidth() const {
  return state_->eye_width;
}
int XrHeadset::eyeHeight() const {
  return state_->eye_height;
}

XrSessionStats XrHeadset::run(const std::function<void(const XrFrameInfo&)>& draw,
                              long long stop_after) {
  State& s = *state_;
  bool exiting = false;
  while (!exiting) {
    XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
    XrResult polled;
    while ((polled = xrPollEvent(s.instance, &event)) == XR_SUCCESS) {
      if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
        const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
        s.session_state = changed.state;
        if (changed.state == XR_SESSION_STATE_READY) {
          XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
          begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
          s.check(xrBeginSession(s.session, &begin), "xrBeginSession");
          s.running = true;
        } else if (changed.state == XR_SESSION_STATE_STOPPING) {
          s.check(xrEndSession(s.session), "xrEndSession");
          s.running = false;
        } else if (changed.state == XR_SESSION_STATE_EXITING ||
                   changed.state == XR_SESSION_STATE_LOSS_PENDING) {
          exiting = true;
        }
      } else if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) {
        exiting = true;
      }
      event = {XR_TYPE_EVENT_DATA_BUFFER};
    }
    s.check(polled, "xrPollEvent");
    if (exiting || !s.running) continue;

    XrFrameWaitInfo wait_info{XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState frame_state{XR_TYPE_FRAME_STATE};
    s.check(xrWaitFrame(s.session, &wait_info, &frame_state), "xrWaitFrame");
    XrFrameBeginInfo begin_info{XR_TYPE_FRAME_BEGIN_INFO};
    s.check(xrBeginFrame(s.session, &begin_info), "xrBeginFrame");

    XrCompositionLayerProjectionView layer_views[2] = {{XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                       {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW}};
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    const XrCompositionLayerBaseHeader* layers[] = {
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
    bool submit = false;
    if (frame_state.shouldRender) {
      XrViewLocateInfo locate{XR_TYPE_VIEW_LOCATE_INFO};
      locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
      locate.displayTime = frame_state.predictedDisplayTime;
      locate.space = s.space;
      XrViewState view_state{XR_TYPE_VIEW_STATE};
      XrView views[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
      uint32_t located = 0;
      s.check(xrLocateViews(s.session, &locate, &view_state, 2, &located, views), "xrLocateViews");
      const XrViewStateFlags needed =
          XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
      if (located == 2 && (view_state.viewStateFlags & needed) == needed) {
        XrEye eyes[2];
        for (int v = 0; v < 2; ++v) {
          const XrView& view = views[v];
          eyes[v].fov = {view.fov.angleLeft, view.fov.angleRight, view.fov.angleUp,
                         view.fov.angleDown};
          eyes[v].pose.position = {view.pose.position.x, view.pose.position.y,
                                   view.pose.position.z};
          eyes[v].pose.orientation = glm::dquat(view.pose.orientation.w, view.pose.orientation.x,
                                                view.pose.orientation.y, view.pose.orientation.z);
          eyes[v].viewport = {v * s.eye_width, 0, s.eye_width, s.eye_height};
          layer_views[v].pose = view.pose;
          layer_views[v].fov = view.fov;
          layer_views[v].subImage.swapchain = s.swapchain;
          layer_views[v].subImage.imageRect.offset = {v * s.eye_width, 0};
          layer_views[v].subImage.imageRect.extent = {s.eye_width, s.eye_height};
          layer_views[v].subImage.imageArrayIndex = 0;
        }
        s.input.head = (eyes[0].pose.position + eyes[1].pose.position) / 2.0;
        s.input.period_s = double(frame_state.predictedDisplayPeriod) * 1e-9;
        s.actions->read(s.space, frame_state.predictedDisplayTime,
                        s.session_state == XR_SESSION_STATE_FOCUSED, s.input);
        uint32_t index = 0;
        XrSwapchainImageAcquireInfo acquire{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
        s.check(xrAcquireSwapchainImage(s.swapchain, &acquire, &index), "xrAcquireSwapchainImage");
        XrSwapchainImageWaitInfo wait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
        wait.timeout = XR_INFINITE_DURATION;
        s.check(xrWaitSwapchainImage(s.swapchain, &wait), "xrWaitSwapchainImage");
        glNamedFramebufferTexture(s.framebuffer, GL_COLOR_ATTACHMENT0, s.images[index].image, 0);
        draw({std::span<const XrEye>(eyes, 2), s.framebuffer, 2 * s.eye_width, s.eye_height,
              s.stats.frames_drawn, &s.input});
        // The runtime reads the image once it is released: the drawing must be finished.
        glFinish();
        XrSwapchainImageReleaseInfo release{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
        s.check(xrReleaseSwapchainImage(s.swapchain, &release), "xrReleaseSwapchainImage");
        layer.space = s.space;
        layer.viewCount = 2;
        layer.views = layer_views;
        submit = true;
      }
    }
    XrFrameEndInfo end{XR_TYPE_FRAME_END_INFO};
    end.displayTime = frame_state.predictedDisplayTime;
    end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    end.layerCount = submit ? 1 : 0;
    end.layers = submit ? layers : nullptr;
    s.check(xrEndFrame(s.session, &end), "xrEndFrame");
    ++s.stats.frames_ended;
    if (submit) ++s.stats.frames_drawn;
    if (((stop_after > 0 && s.stats.frames_drawn >= stop_after) || exit_wanted_) &&
        s.session_state != XR_SESSION_STATE_STOPPING) {
      exit_wanted_ = false;
      s.check(xrRequestExitSession(s.session), "xrRequestExitSession");
      stop_after = 0;
    }
  }
  return s.stats;
}

}  // namespace parallax
