#include "sim/policy/scripted_oracle.h"

#include <algorithm>

#include "sim/core/pose.h"
#include "sim/robot/inverse_kinematics.h"
#include "sim/robot/kinematics.h"
#include "sim/task/instruction_parser.h"

namespace culinarycut {
namespace {

std::string ObjectList(const std::vector<task::ObjectBox>& objects) {
  std::string names;
  for (const auto& object : objects) {
    names += (names.empty() ? "" : ", ") + object.name + " (" + object.food + ")";
  }
  return names.empty() ? "no objects" : names;
}

Eigen::Isometry3d TcpInWorld(const Model& model, const Eigen::VectorXd& qpos_rad) {
  return model.robot_base_in_world * TipPose(model.robot, qpos_rad, model.tcp_in_last_link);
}

}  // namespace

const task::ObjectBox& FindTargetObject(const std::vector<task::ObjectBox>& objects,
                                        const task::CutSpec& spec, const std::string& target_name) {
  const task::ObjectBox* found = nullptr;
  for (const auto& object : objects) {
    if (!target_name.empty() ? object.name == target_name : object.food == spec.target_object) {
      if (found) {
        throw task::TaskError("the scene has more than one " + spec.target_object + " (" +
                              ObjectList(objects) + "); name the one to cut");
      }
      found = &object;
    }
  }
  if (!found) {
    throw task::TaskError("the task asks for " +
                          (target_name.empty() ? "a " + spec.target_object : "'" + target_name + "'") +
                          " but the scene has " + ObjectList(objects));
  }
  if (found->food != spec.target_object) {
    throw task::TaskError("object '" + found->name + "' is a " + found->food + ", not the " +
                          spec.target_object + " the task asks to cut");
  }
  return *found;
}

ScriptedOracle::ScriptedOracle(const Model& model, const OracleConfig& config,
                               const Eigen::VectorXd& qpos_rad, double now_s)
    : control_mode_(config.control_mode), start_time_s_(now_s) {
  const task::CutSpec spec = config.spec ? *config.spec : task::ParseInstruction(config.instruction);
  task::ValidateCutSpec(spec);
  target_ = FindTargetObject(config.objects, spec, config.target_name);
  trajectory_ = task::PlanCutTrajectory(target_, spec, TcpInWorld(model, qpos_rad), config.planner,
                                        config.seed);
}

Eigen::VectorXd ScriptedOracle::Act(const Model& model, const Eigen::VectorXd& qpos_rad,
                                    double now_s) const {
  // Aim where the plan will be when this control step ends.
  const double plan_time_s = now_s - start_time_s_ + model.control_timestep_s;
  const Eigen::Isometry3d goal = trajectory_.Sample(plan_time_s).tcp_pose;
  const Eigen::Isometry3d goal_in_base = model.robot_base_in_world.inverse() * goal;
  const Eigen::Isometry3d tcp_in_base = model.robot_base_in_world.inverse() * TcpInWorld(model, qpos_rad);
  // Normalised modes: the step's motion divided by what [-1, 1] means, clipped as the controller would.
  const Eigen::Vector3d position_step = (goal_in_base.translation() - tcp_in_base.translation()) / kDeltaPositionScaleM;
  switch (control_mode_) {
    case ControlMode::kEndEffectorPoseQuat:
      return PoseToVector(goal);
    case ControlMode::kEndEffectorPose: {
      Eigen::VectorXd pose(6);
      pose << goal_in_base.translation(), EulerXyzFromRotation(goal_in_base.linear());
      return pose;
    }
    case ControlMode::kEndEffectorDeltaPosition:
      return position_step.cwiseMax(-1.0).cwiseMin(1.0);
    case ControlMode::kEndEffectorDeltaPose: {
      Eigen::VectorXd delta(6);
      delta.head<3>() = position_step.cwiseMax(-1.0).cwiseMin(1.0);
      // The controller applies q = dq * q_tcp in the root frame: dq = q_goal * q_tcp^-1.
      Eigen::Vector3d rotation_step =
          EulerXyzFromRotation(goal_in_base.linear() * tcp_in_base.linear().transpose()) / kDeltaRotationScaleRad;
      if (rotation_step.norm() > 1.0) rotation_step.normalize();
      delta.tail<3>() = rotation_step;
      return delta;
    }
    case ControlMode::kJointPosition:
    case ControlMode::kJointDeltaPosition: {
      const IkResult ik =
          SolveInverseKinematics(model.robot, model.tcp_in_last_link, goal_in_base, qpos_rad);
      if (control_mode_ == ControlMode::kJointPosition) return ik.q_rad;
      return ((ik.q_rad - qpos_rad) / kDeltaJointScaleRad).cwiseMax(-1.0).cwiseMin(1.0);
    }
  }
  return {};
}

}  // namespace culinarycut
