#include "server/safety_model.h"

#include <spdlog/spdlog.h>

namespace culinarycut::server {

SafetyModelSource LoadSafetyModel(const std::string& path) {
  SafetyModelSource source;
  source.path = path;
  try {
    source.model = std::make_shared<const safety::ForceModel>(safety::LoadForceModel(path));
    spdlog::info("safety force model {}: version {}, {} terms", path, source.model->version, source.model->terms.size());
  } catch (const safety::ForceModelError& error) {
    source.error = error.what();
    spdlog::warn("no safety limiter: {} (scenes with effects.safety_limiter will be refused)", source.error);
  }
  return source;
}

}  // namespace culinarycut::server
