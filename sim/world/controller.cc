#include "sim/world/controller.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/core/pose.h"
#include "sim/robot/kinematics.h"

namespace culinarycut {
namespace {

// Clips values to bounds in place; returns whether anything changed.
bool ClipToBounds(Eigen::VectorXd* values, const ActionBounds& bounds) {
  bool clipped = false;
  for (int i = 0; i < values->size(); ++i) {
    const double clamped = std::clamp((*values)[i], bounds.low[i], bounds.high[i]);
    clipped |= clamped != (*values)[i];
    (*values)[i] = clamped;
  }
  return clipped;
}

}  // namespace

std::optional<std::string> ValidateAction(const Model& model, const Action& action) {
  const size_t expected = ActionBoundsFor(model, action.mode).low.size();
  std::ostringstream error;
  if (static_cast<size_t>(action.values.size()) != expected) {
    error << "action.values must have " << expected << " elements for control mode " << ControlModeName(action.mode)
          << ", got " << action.values.size();
    return error.str();
  }
  for (int i = 0; i < action.values.size(); ++i) {
    if (!std::isfinite(action.values[i])) {
      error << "action.values[" << i << "] is " << (std::isnan(action.values[i]) ? "NaN" : "infinite")
            << "; every element must be a finite number";
      return error.str();
    }
  }
  if (action.mode == ControlMode::kEndEffectorPose && action.values.segment<4>(3).cwiseAbs().maxCoeff() == 0.0) {
    return "action.values[3:7] (quaternion qw, qx, qy, qz) has zero norm; give a unit quaternion, e.g. [0, 1, 0, 0] "
           "for the knife pointing down";
  }
  return std::nullopt;
}

JointTarget ComputeJointTarget(const Model& model, const Eigen::VectorXd& q_measured_rad, const Action& action) {
  JointTarget target;
  Eigen::VectorXd values = action.values;
  // A quaternion of any positive norm is valid (ValidateAction refused zero): normalise it, so
  // clipping never changes its direction.
  if (action.mode == ControlMode::kEndEffectorPose) {
    values.segment<4>(3) = *NormalizedQuaternion(values.segment<4>(3));
  }
  target.clipped = ClipToBounds(&values, ActionBoundsFor(model, action.mode));
  switch (action.mode) {
    case ControlMode::kJointPosition:
      target.q_target_rad = values;
      return target;
    case ControlMode::kJointDeltaPosition:
      target.q_target_rad = ClampToJointLimits(model.robot, q_measured_rad + values, 0.0);
      return target;
    case ControlMode::kEndEffectorPose:
    case ControlMode::kEndEffectorDeltaPose:
      break;
  }
  // Goals are built in the world frame, then moved into the robot base frame for IK.
  Eigen::Isometry3d goal_in_world;
  if (action.mode == ControlMode::kEndEffectorPose) {
    goal_in_world = PoseFromVector(values);
  } else {
    goal_in_world = model.robot_base_in_world * TipPose(model.robot, q_measured_rad, model.tcp_in_last_link);
    goal_in_world.translation() += values.head<3>();
    goal_in_world.linear() = RotationFromAxisAngle(values.tail<3>()) * goal_in_world.linear();
  }
  const Eigen::Isometry3d goal_in_base = model.robot_base_in_world.inverse() * goal_in_world;
  target.ik = SolveInverseKinematics(model.robot, model.tcp_in_last_link, goal_in_base, q_measured_rad);
  target.q_target_rad = target.ik->q_rad;
  return target;
}

JointVector JointVelocityCommand(const Model& model, JointValues q_rad, JointValues q_target_rad) {
  JointVector command = model.config.robot.joint_stiffness_per_s * (q_target_rad - q_rad);
  // Scale the whole command, not each joint alone: clamping joints separately bends the joint-space
  // direction and the knife leaves its straight path.
  double worst_ratio = 1.0;
  for (int i = 0; i < command.size(); ++i) {
    worst_ratio = std::max(worst_ratio, std::abs(command[i]) / model.robot.limits[i].max_velocity_rad_s);
  }
  return command / worst_ratio;
}

}  // namespace culinarycut
