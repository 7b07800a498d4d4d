// One control step: control -> physics substeps -> bookkeeping, each stage timed.
#pragma once

#include <optional>

#include "sim/robot/inverse_kinematics.h"
#include "sim/world/controller.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

struct StepReport {
  bool action_clipped = false;
  std::optional<IkResult> ik;     // end-effector modes only
  bool truncated = false;         // max_episode_steps reached
  int substeps = 0;
  double wall_time_ms = 0.0;
  double control_wall_time_ms = 0.0;   // action -> joint targets (IK included)
  double physics_wall_time_ms = 0.0;   // the physics substeps
};

// Preconditions: state has been reset and ValidateAction(model, action) found nothing.
StepReport Step(const Model& model, State* state, const Action& action);

}  // namespace culinarycut
