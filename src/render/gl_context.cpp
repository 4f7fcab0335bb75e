#include "render/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace parallax {

namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[length] == ' ' || p[length] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default: {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "0x%04x", unsigned(error));
      return buffer;
    }
  }
}

const char* debugSourceName(GLenum source) {
  switch (source) {
    case GL_DEBUG_SOURCE_API:
      return "api";
    case GL_DEBUG_SOURCE_SHADER_COMPILER:
      return "shader compiler";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
      return "window system";
    case GL_DEBUG_SOURCE_APPLICATION:
      return "application";
    default:
      return "other";
  }
}

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                               const GLchar* message, const void*) {
  // Notifications are chatty on Mesa (buffer placement hints); keep them out of the log.
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  std::fprintf(stderr, "parallax: GL %s%s (id %u): %s\n", debugSourceName(source),
               type == GL_DEBUG_TYPE_ERROR ? " error" : "", id, message);
}

void enableDebugOutput() {
  if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43) return;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(onDebugMessage, nullptr);
}

std::string glString(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text ? text : "(unknown)";
}

constexpr int kNeedMajor = 4;
constexpr int kNeedMinor = 5;

std::string needText() {
  return "Parallax needs OpenGL 4.5 core (Mesa 20 or later gives it even without a GPU through "
         "llvmpipe: install the Debian package 'libgl1-mesa-dri')";
}

}  // namespace

bool glDebugRequested() {
  if (const char* env = std::getenv("PARALLAX_GL_DEBUG")) return std::strcmp(env, "0") != 0;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

struct GlContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  ~Egl() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
  }
};

namespace {

struct Candidate {
  EGLDisplay display;
  std::string name;
};

// The displays to try, best first. Mesa's surfaceless platform needs no X or GBM device; the
// device platform is how NVIDIA's driver offers headless contexts.
std::vector<Candidate> candidateDisplays(std::string& notes) {
  std::vector<Candidate> result;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool platform_base = hasExtension(client, "EGL_EXT_platform_base");
  if (platform_base && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display != EGL_NO_DISPLAY) result.push_back({display, "EGL surfaceless"});
  }
  if (platform_base && hasExtension(client, "EGL_EXT_platform_device") &&
      hasExtension(client, "EGL_EXT_device_enumeration")) {
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (eglQueryDevicesEXT(8, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display != EGL_NO_DISPLAY) {
          result.push_back({display, "EGL device " + std::to_string(i)});
        }
      }
    }
  }
  if (EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY); display != EGL_NO_DISPLAY) {
    result.push_back({display, "EGL default display"});
  }
  if (result.empty()) {
    notes += "no EGL display found (client extensions: ";
    notes += client ? client : "none";
    notes += "); ";
  }
  return result;
}

EGLContext createEglContext(EGLDisplay display, bool debug, bool any_version) {
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                      EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  // Surfaceless contexts need no config; pass one when the display has it (some drivers insist).
  if (!eglChooseConfig(display, config_attributes, &config, 1, &config_count) ||
      config_count == 0) {
    config = EGL_NO_CONFIG_KHR;
  }
  std::vector<EGLint> attributes;
  if (!any_version) {
    attributes = {EGL_CONTEXT_MAJOR_VERSION,       kNeedMajor,
                  EGL_CONTEXT_MINOR_VERSION,       kNeedMinor,
                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debug) attributes.insert(attributes.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
  }
  attributes.push_back(EGL_NONE);
  return eglCreateContext(display, config, EGL_NO_CONTEXT, attributes.data());
}

}  // namespace

std::unique_ptr<GlContext> GlContext::createHeadless(const GlContextOptions& options) {
  const bool debug = options.debug || glDebugRequested();
  std::string notes;
  for (const Candidate& candidate : candidateDisplays(notes)) {
    auto egl = std::make_unique<Egl>();
    EGLint major = 0, minor = 0;
    if (!eglInitialize(candidate.display, &major, &minor)) {
      notes += candidate.name + ": eglInitialize failed (" + eglErrorName(eglGetError()) + "); ";
      continue;
    }
    egl->display = candidate.display;
    const char* extensions = eglQueryString(candidate.display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) {
      notes += candidate.name + ": no EGL_KHR_surfaceless_context; ";
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      notes += candidate.name + ": no desktop OpenGL API; ";
      continue;
    }
    egl->context = createEglContext(candidate.display, debug, false);
    if (egl->context == EGL_NO_CONTEXT) {
      const EGLint error = eglGetError();  // before the probe below resets it
      // Say what the driver does offer: the best message for an old Mesa or a GLES-only GPU.
      EGLContext fallback = createEglContext(candidate.display, false, true);
      std::string offered = "none";
      if (fallback != EGL_NO_CONTEXT &&
          eglMakeCurrent(candidate.display, EGL_NO_SURFACE, EGL_NO_SURFACE, fallback)) {
        offered = glString(GL_VERSION) + " on " + glString(GL_RENDERER);
        eglMakeCurrent(candidate.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      }
      if (fallback != EGL_NO_CONTEXT) eglDestroyContext(candidate.display, fallback);
      notes += candidate.name + ": no 4.5 core context (" + eglErrorName(error) +
               "; the driver offers OpenGL " + offered + "); ";
      continue;
    }
    if (!eglMakeCurrent(candidate.display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl->context)) {
      notes += candidate.name + ": eglMakeCurrent failed; ";
      continue;
    }
    std::unique_ptr<GlContext> context(new GlContext());
    context->egl_ = std::move(egl);
    context->describe(candidate.name, debug);
    return context;
  }
  throw GlContextError("no headless OpenGL 4.5 context: " + notes + needText());
}

std::unique_ptr<GlContext> GlContext::adoptCurrent(const GlContextOptions& options) {
  std::unique_ptr<GlContext> context(new GlContext());
  context->describe("window", options.debug || glDebugRequested());
  return context;
}

void GlContext::describe(std::string platform, bool debug) {
  platform_ = std::move(platform);
  version_ = glString(GL_VERSION);
  renderer_ = glString(GL_RENDERER);
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  if (major * 10 + minor < kNeedMajor * 10 + kNeedMinor) {
    throw GlContextError("the " + platform_ + " context is OpenGL " + version_ + " on " +
                         renderer_ + "; " + needText());
  }
  if (debug) enableDebugOutput();
}

GlContext::~GlContext() = default;

}  // namespace parallax
