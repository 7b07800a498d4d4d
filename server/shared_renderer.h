// The process's one renderer (one EGL context on its own thread, shared by every session; see
// docs/rendering.md). It starts when the first session that declares cameras is created, so a
// server whose clients never ask for images never touches EGL. A start that fails is reported to
// that client and tried again by the next one.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "sim/render/renderer.h"

namespace culinarycut::server {

class SharedRenderer {
 public:
  explicit SharedRenderer(render::RendererOptions options) : options_(std::move(options)) {}

  // The renderer, started on first use. Throws render::RenderError when EGL cannot start.
  render::Renderer& Get();
  // e.g. "llvmpipe ..., EGL surfaceless"; empty until started.
  std::string device_description() const;

 private:
  const render::RendererOptions options_;
  mutable std::mutex mutex_;
  std::unique_ptr<render::Renderer> renderer_;
};

}  // namespace culinarycut::server
