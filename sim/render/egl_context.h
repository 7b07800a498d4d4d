// A headless OpenGL 3.3+ core context through EGL, with no window and no surface: rendering goes
// into framebuffer objects. Either the EGL device platform (a GPU, e.g. NVIDIA) or Mesa's
// surfaceless platform (llvmpipe on a CPU-only machine).
#pragma once

#include <memory>
#include <string>

namespace culinarycut::render {

enum class EglBackend {
  kAuto,         // a hardware EGL device when one exists, else Mesa surfaceless
  kSurfaceless,  // EGL_PLATFORM_SURFACELESS_MESA (llvmpipe, or Mesa's GPU drivers)
  kDevice,       // EGL_EXT_platform_device; the first device that is not a software rasteriser
};

// Parses "auto" | "surfaceless" | "device"; throws RenderError listing the choices otherwise.
EglBackend ParseEglBackend(const std::string& name);

// Owns the EGL display and context. The context is current on the thread that created it and must
// only be used there (see RenderThread). Not copyable.
class EglContext {
 public:
  // Throws RenderError naming the failed step and the EGL error code.
  static std::unique_ptr<EglContext> Create(EglBackend backend);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless"
  const std::string& description() const { return description_; }
  bool is_software() const { return is_software_; }

 private:
  EglContext() = default;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string description_;
  bool is_software_ = false;
};

}  // namespace culinarycut::render
