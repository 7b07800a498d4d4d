// One control step as named, timed stages: robot control -> per physics step (robot physics ->
// knife pose from the TCP -> MPM substeps -> wrench back on the robot) -> topology -> bookkeeping.
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
  int substeps = 0;               // robot physics steps
  int mpm_substeps = 0;           // MPM substeps (0 while the food sleeps or without food)
  bool knife_contact = false;     // the knife touched the food during this step
  bool first_contact = false;     // ... for the first time this episode (the contact phase begins)
  double wall_time_ms = 0.0;
  double control_wall_time_ms = 0.0;   // action -> joint targets (IK included)
  double physics_wall_time_ms = 0.0;   // the robot's physics substeps
  double mpm_wall_time_ms = 0.0;       // the food's MPM substeps
  double topology_wall_time_ms = 0.0;  // piece detection
};

// Preconditions: state has been reset and ValidateAction(model, action) found nothing.
StepReport Step(const Model& model, State* state, const Action& action);

}  // namespace culinarycut
