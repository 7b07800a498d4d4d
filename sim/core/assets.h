// Where the data files (robot description, language templates) live.
#pragma once

#include <string>

namespace culinarycut {

// $CULINARYCUT_ASSETS_DIR when set, else the source tree's assets/ folder baked in at build time.
std::string AssetsDir();

}  // namespace culinarycut
