#include "sim/render/egl_context.h"

#include <cstdio>
#include <cstring>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "sim/render/gl.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

constexpr const char* kInstallHint =
    "; on a CPU-only machine install Mesa's EGL and llvmpipe (Debian: libegl1 libegl-mesa0 "
    "libgl1-mesa-dri), on an NVIDIA machine the driver's EGL library (libnvidia-egl); "
    "if __EGL_VENDOR_LIBRARY_FILENAMES is set, check that it names an existing vendor json";

std::string EglErrorName(EGLint code) {
  switch (code) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: break;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "0x%04x", static_cast<unsigned>(code));
  return buffer;
}

[[noreturn]] void Fail(const std::string& step) {
  throw RenderError("EGL could not start: " + step + " failed (EGL error " + EglErrorName(eglGetError()) + ")" +
                    kInstallHint);
}

bool HasExtension(const char* extensions, const char* name) {
  if (extensions == nullptr) return false;
  const size_t length = std::strlen(name);
  for (const char* at = std::strstr(extensions, name); at != nullptr; at = std::strstr(at + 1, name)) {
    const bool starts = at == extensions || at[-1] == ' ';
    const bool ends = at[length] == '\0' || at[length] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

// A hardware EGL device's display, or EGL_NO_DISPLAY when there is none (software devices skipped).
EGLDisplay FindHardwareDeviceDisplay(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!HasExtension(client, "EGL_EXT_platform_device")) return EGL_NO_DISPLAY;
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_device_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (query_devices == nullptr || query_device_string == nullptr) return EGL_NO_DISPLAY;
  EGLint count = 0;
  if (!query_devices(0, nullptr, &count) || count <= 0) return EGL_NO_DISPLAY;
  std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
  if (!query_devices(count, devices.data(), &count)) return EGL_NO_DISPLAY;
  for (EGLint i = 0; i < count; ++i) {
    const char* extensions = query_device_string(devices[i], EGL_EXTENSIONS);
    if (HasExtension(extensions, "EGL_MESA_device_software")) continue;
    EGLDisplay display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    if (display != EGL_NO_DISPLAY) return display;
  }
  return EGL_NO_DISPLAY;
}

}  // namespace

EglBackend ParseEglBackend(const std::string& name) {
  if (name == "auto" || name.empty()) return EglBackend::kAuto;
  if (name == "surfaceless") return EglBackend::kSurfaceless;
  if (name == "device") return EglBackend::kDevice;
  throw RenderError("unknown EGL backend '" + name + "'; choose auto, surfaceless or device");
}

std::unique_ptr<EglContext> EglContext::Create(EglBackend backend) {
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) Fail("eglGetProcAddress(eglGetPlatformDisplayEXT)");

  // Pick the display: a hardware device first (auto/device), else Mesa surfaceless.
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
  if (backend != EglBackend::kSurfaceless) {
    display = FindHardwareDeviceDisplay(get_platform_display);
    if (display != EGL_NO_DISPLAY) platform = "EGL device";
    if (display == EGL_NO_DISPLAY && backend == EglBackend::kDevice) {
      Fail("finding a hardware EGL device (EGL_EXT_platform_device, no software devices)");
    }
  }
  if (display == EGL_NO_DISPLAY) {
    display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) Fail("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
    platform = "EGL surfaceless";
  }

  auto context = std::unique_ptr<EglContext>(new EglContext());
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) Fail("eglInitialize (" + platform + ")");
  context->display_ = display;

  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  if (!eglChooseConfig(display, config_attributes, &config, 1, &config_count) || config_count < 1) {
    Fail("eglChooseConfig (no surfaceless OpenGL config)");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) Fail("eglBindAPI(EGL_OPENGL_API)");
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_NONE};
  EGLContext egl_context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (egl_context == EGL_NO_CONTEXT) Fail("eglCreateContext (OpenGL 3.3 core)");
  context->context_ = egl_context;
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context)) Fail("eglMakeCurrent (no surface)");

  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  if (renderer == nullptr || version == nullptr) {
    throw RenderError("EGL started but OpenGL does not answer glGetString(GL_RENDERER)" + std::string(kInstallHint));
  }
  GLint gl_major = 0, gl_minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
  if (gl_major * 10 + gl_minor < 33) {
    throw RenderError(std::string("OpenGL 3.3 core is required, the context has ") + version + " (" + renderer + ")");
  }
  context->description_ = std::string(renderer) + ", OpenGL " + version + ", " + platform;
  const std::string renderer_name = renderer;
  context->is_software_ = renderer_name.find("llvmpipe") != std::string::npos ||
                          renderer_name.find("softpipe") != std::string::npos;
  return context;
}

EglContext::~EglContext() {
  if (display_ == nullptr) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != nullptr) eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

}  // namespace culinarycut::render
