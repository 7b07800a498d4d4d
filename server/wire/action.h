// Actions on the wire: a control mode by name and its values. Throws FieldError naming the field.
#pragma once

#include <string>

#include "culinarycut/v1/simulator.pb.h"
#include "sim/world/controller.h"

namespace culinarycut::server {

// The mode named `name` (empty: the default mode); an unknown name lists the known ones.
ControlMode ControlModeFromWire(const std::string& name, const std::string& field);

// The mode and values of a StepRequest's action; the values are checked against the model by
// ValidateAction.
Action ActionFromWire(const v1::Action& wire);

}  // namespace culinarycut::server
