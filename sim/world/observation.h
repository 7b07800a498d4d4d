// What a client sees of the robot: ManiSkill's agent/qpos, agent/qvel and the knife TCP.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "sim/core/pose.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

struct RobotObservation {
  std::uint64_t frame_id = 0;
  double sim_time_s = 0.0;
  Eigen::VectorXd qpos_rad;
  Eigen::VectorXd qvel_rad_s;
  Eigen::VectorXd qpos_target_rad;
  Vector7d tcp_pose;        // [x, y, z, qw, qx, qy, qz], world
  Vector6d tcp_velocity;    // [vx, vy, vz] (m/s) and [wx, wy, wz] (rad/s), world
  Vector7d flange_pose;     // [x, y, z, qw, qx, qy, qz], world
  // The food's wrench on the knife over the last control step as a wrist sensor at the flange
  // reads it: [fx, fy, fz] (N), [tx, ty, tz] (N m), flange frame. Zero without food.
  Vector6d wrist_wrench = Vector6d::Zero();
};

// Precondition: state has been reset.
RobotObservation Observe(const Model& model, const State& state);

}  // namespace culinarycut
