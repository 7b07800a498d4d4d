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
  if (action.mode == ControlMode::kEndEffectorPoseQuat && action.values.segment<4>(3).cwiseAbs().maxCoeff() == 0.0) {
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
  if (action.mode == ControlMode::kEndEffectorPoseQuat) {
    values.segment<4>(3) = *NormalizedQuaternion(values.segment<4>(3));
  }
  if (action.mode == ControlMode::kEndEffectorDeltaPose) {
    // ManiSkill3 PDEEPoseController._clip_and_scale_action: position clipped per element, the
    // rotation by its norm, so a large rotation keeps its axis.
    Eigen::VectorXd position = values.head<3>();
    target.clipped = ClipToBounds(&position, ActionBounds{{-1, -1, -1}, {1, 1, 1}, ""});
    values.head<3>() = position;
    const double rotation_norm = values.tail<3>().norm();
    if (rotation_norm > 1.0) {
      values.tail<3>() /= rotation_norm;
      target.clipped = true;
    }
  } else {
    target.clipped = ClipToBounds(&values, ActionBoundsFor(model, action.mode));
  }
  const Eigen::Isometry3d base_to_world = model.robot_base_in_world;
  Eigen::Isometry3d goal_in_base = Eigen::Isometry3d::Identity();
  switch (action.mode) {
    case ControlMode::kJointPosition:
      target.q_target_rad = values;
      return target;
    case ControlMode::kJointDeltaPosition:  // ManiSkill3 PDJointPosController, use_delta: qpos + action
      target.q_target_rad = ClampToJointLimits(model.robot, q_measured_rad + kDeltaJointScaleRad * values, 0.0);
      return target;
    case ControlMode::kEndEffectorDeltaPosition:
    case ControlMode::kEndEffectorDeltaPose:
      // ManiSkill3 PDEEPoseController.compute_target_pose, frame "root_translation:root_aligned_body_rotation":
      // p = p_tcp + dp and q = dq * q_tcp, both in the root frame, from the measured TCP pose.
      goal_in_base = TipPose(model.robot, q_measured_rad, model.tcp_in_last_link);
      goal_in_base.translation() += kDeltaPositionScaleM * values.head<3>();
      if (action.mode == ControlMode::kEndEffectorDeltaPose) {
        goal_in_base.linear() = RotationFromEulerXyz(kDeltaRotationScaleRad * values.tail<3>()) * goal_in_base.linear();
      }
      break;
    case ControlMode::kEndEffectorPose:  // ManiSkill3 PDEEPoseController, use_delta false: [p, XYZ Euler] in the root
      goal_in_base.translation() = values.head<3>();
      goal_in_base.linear() = RotationFromEulerXyz(values.tail<3>());
      break;
    case ControlMode::kEndEffectorPoseQuat:
      goal_in_base = base_to_world.inverse() * PoseFromVector(values);
      break;
  }
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
