// The safety limiter's force model as the server holds it: loaded once at start from --safety-model
// (default: the installed asset), or the reason it could not be, which a scene asking for the limiter
// then gets as FAILED_PRECONDITION (the server still starts).
#pragma once

#include <memory>
#include <string>

#include "sim/safety/force_model.h"

namespace culinarycut::server {

struct SafetyModelSource {
  std::string path;
  std::shared_ptr<const safety::ForceModel> model;  // null when it could not be loaded
  std::string error;                                // why not, naming the file and the JSON field
};

// Never throws: a missing or invalid file is reported in `error` (and logged).
SafetyModelSource LoadSafetyModel(const std::string& path);

}  // namespace culinarycut::server
