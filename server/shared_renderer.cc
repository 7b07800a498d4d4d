#include "server/shared_renderer.h"

#include <spdlog/spdlog.h>

namespace culinarycut::server {

render::Renderer& SharedRenderer::Get() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!renderer_) {
    renderer_ = render::Renderer::Create(options_);
    spdlog::info("renderer started: {}", renderer_->device_description());
  }
  return *renderer_;
}

std::string SharedRenderer::device_description() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return renderer_ ? renderer_->device_description() : std::string();
}

}  // namespace culinarycut::server
