#include "sim/world/observation.h"

#include "sim/robot/kinematics.h"

namespace culinarycut {

RobotObservation Observe(const Model& model, const State& state) {
  RobotObservation observation;
  observation.frame_id = state.frame_id;
  observation.sim_time_s = state.sim_time_s;
  observation.qpos_rad = state.physics->JointPositions();
  observation.qvel_rad_s = state.physics->JointVelocities();
  observation.qpos_target_rad = state.q_target_rad;
  const Eigen::Isometry3d last_link = model.robot_base_in_world * ForwardKinematics(model.robot, observation.qpos_rad);
  observation.tcp_pose = PoseToVector(last_link * model.tcp_in_last_link);
  observation.flange_pose = PoseToVector(last_link * model.flange_in_last_link);
  observation.tcp_velocity = TipJacobian(model.robot, observation.qpos_rad, model.tcp_in_last_link) * observation.qvel_rad_s;
  return observation;
}

}  // namespace culinarycut
