// What a client sees of a (Model, State) (MuJoCo's mj_forward for sensors): the robot as
// ManiSkill's agent/qpos, agent/qvel and the knife TCP; the wrist wrench; the food's pieces and
// contact; the instruction and task score; and the images of the scene's cameras.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/core/pose.h"
#include "sim/core/stage_timer.h"
#include "sim/mpm/topology.h"
#include "sim/render/camera_renderer.h"
#include "sim/task/success_metrics.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

struct RobotObservation {
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

struct FoodObservation {
  bool knife_contact = false;      // the knife touched the food during the last control step
  bool mpm_awake = false;          // MPM substeps ran during the last control step
  std::vector<mpm::Piece> pieces;  // from the last topology update
};

struct Observation {
  std::uint64_t frame_id = 0;
  double sim_time_s = 0.0;
  RobotObservation robot;
  std::optional<FoodObservation> food;        // only when the scene has food
  std::string instruction;                    // the scene task's; empty without a task
  std::optional<task::TaskScore> task_score;  // only when the scene declares a task
  std::optional<safety::EpisodeSafety> safety;  // only with effects.safety_limiter
  render::RenderResult images;                // the scene's cameras, when a renderer was given
  double render_wall_time_ms = 0.0;           // measurement only, never part of the simulation
};

// Precondition: state has been reset. Renders model.cameras with `renderer` when it is given and the
// scene has cameras (throws render::RenderError); without one the images stay empty.
Observation Observe(const Model& model, const State& state, render::CameraRenderer* renderer = nullptr);

// The robot part alone (no food, task or images): what telemetry and controllers need.
RobotObservation ObserveRobot(const Model& model, const State& state);

}  // namespace culinarycut
