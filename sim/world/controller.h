// Turns an action into joint position targets, and targets into joint velocity commands for the
// motors (the PD law in velocity-servo form: qdot = k (q_target - q), scaled down as a whole to the
// joint speed limits).
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "sim/robot/inverse_kinematics.h"
#include "sim/robot/kinematics.h"
#include "sim/world/control_mode.h"
#include "sim/world/model.h"

namespace culinarycut {

struct Action {
  ControlMode mode = ControlMode::kJointDeltaPosition;
  Eigen::VectorXd values;
};

// An error naming the offending element ("action.values[3] is NaN"), or nothing when the action is usable.
std::optional<std::string> ValidateAction(const Model& model, const Action& action);

struct JointTarget {
  Eigen::VectorXd q_target_rad;
  bool clipped = false;          // some action element was outside its bounds
  std::optional<IkResult> ik;    // set for end-effector modes
};

// Joint targets for a validated action, given the measured joint positions.
JointTarget ComputeJointTarget(const Model& model, const Eigen::VectorXd& q_measured_rad, const Action& action);

// Motor velocity command (rad/s) towards the target, within every joint's speed limit, its direction kept.
// Allocates nothing: it runs once per physics substep.
JointVector JointVelocityCommand(const Model& model, JointValues q_rad, JointValues q_target_rad);

}  // namespace culinarycut
