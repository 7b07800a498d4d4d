// The safety limiter's force model on the wire (GetServerInfo.safety_model).
#pragma once

#include <string>

#include "culinarycut/v1/simulator.pb.h"
#include "sim/safety/force_model.h"

namespace culinarycut::server {

// `model` may be null: then only the path and the load error are filled in.
void ForceModelToWire(const std::string& path, const safety::ForceModel* model, const std::string& load_error,
                      v1::SafetyModelInfo* wire);

}  // namespace culinarycut::server
