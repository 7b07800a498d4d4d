#include "sim/core/assets.h"

#include <cstdlib>

namespace culinarycut {

std::string AssetsDir() {
  const char* assets = std::getenv("CULINARYCUT_ASSETS_DIR");
  return (assets && *assets) ? assets : CULINARYCUT_ASSETS_DIR;
}

}  // namespace culinarycut
