#include "sim/world/step.h"

#include <chrono>

#include "sim/robot/kinematics.h"
#include "sim/world/food_step.h"

namespace culinarycut {
namespace {

Eigen::Isometry3d TcpInWorld(const Model& model, const Eigen::VectorXd& q_rad) {
  return model.robot_base_in_world * TipPose(model.robot, q_rad, model.tcp_in_last_link);
}

// Joint torques (N m) that put the food's wrench on the knife TCP: tau = J^T [f; t] (base frame).
Eigen::VectorXd KnifeWrenchTorques(const Model& model, const Eigen::VectorXd& q_rad, const KnifeWrench& wrench) {
  const Eigen::Matrix3d world_to_base = model.robot_base_in_world.linear().transpose();
  Eigen::Matrix<double, 6, 1> wrench_in_base;
  wrench_in_base << world_to_base * wrench.force_n, world_to_base * wrench.torque_nm;
  return TipJacobian(model.robot, q_rad, model.tcp_in_last_link).transpose() * wrench_in_base;
}

}  // namespace

StepReport Step(const Model& model, State* state, const Action& action) {
  const auto start = std::chrono::steady_clock::now();
  StepReport report;
  {
    ScopedStageTimer timer(&state->timers, Stage::kControl, &report.control_wall_time_ms);
    JointTarget target = ComputeJointTarget(model, state->physics->JointPositions(), action);
    state->q_target_rad = target.q_target_rad;
    report.action_clipped = target.clipped;
    report.ik = target.ik;
  }
  FoodState* food = state->food.get();
  KnifeWrench wrench_sum;  // over the physics steps, for the control step's mean
  // The PD loop runs at the physics rate: a fresh velocity command every substep, on top of
  // gravity compensation (as the Panda's own controller does), so the servo only handles motion.
  const Eigen::Vector3d gravity_in_base = model.robot_base_in_world.linear().transpose() * model.layout.gravity_m_s2;
  // The knife's pose at the start of each physics step is the pose at the end of the one before.
  Eigen::Isometry3d tcp_start = food ? TcpInWorld(model, state->physics->JointPositions()) : Eigen::Isometry3d::Identity();
  for (int i = 0; i < model.substeps_per_control_step; ++i) {
    const Eigen::VectorXd q = state->physics->JointPositions();
    {
      const auto robot_start = std::chrono::steady_clock::now();
      state->physics->AddJointTorques(GravityTorques(model.robot, q, gravity_in_base));
      Eigen::VectorXd qdot_command = JointVelocityCommand(model, q, state->q_target_rad);
      if (food) {
        // Two-way coupling: the food's wrench from the last physics step acts on the knife, and
        // the speed resistance slows the servo while the knife is in the food.
        state->physics->AddJointTorques(KnifeWrenchTorques(model, q, food->wrench));
        qdot_command *= food->knife_speed_factor;
      }
      state->physics->SetJointVelocityCommand(qdot_command);
      state->physics->StepOnce();
      const double elapsed_ms = MillisecondsSince(robot_start);
      report.physics_wall_time_ms += elapsed_ms;
      state->timers.total_seconds[static_cast<int>(Stage::kPhysics)] += 1e-3 * elapsed_ms;
    }
    if (food) {
      const auto mpm_start = std::chrono::steady_clock::now();
      const Eigen::Isometry3d tcp_end = TcpInWorld(model, state->physics->JointPositions());
      const FoodStepReport food_report = AdvanceFood(*model.food, tcp_start, tcp_end, model.physics_timestep_s, food);
      tcp_start = tcp_end;
      report.mpm_substeps += food_report.substeps;
      report.knife_contact = report.knife_contact || food_report.contact;
      wrench_sum.force_n += food->wrench.force_n;
      wrench_sum.torque_nm += food->wrench.torque_nm;
      const double elapsed_ms = MillisecondsSince(mpm_start);
      report.mpm_wall_time_ms += elapsed_ms;
      state->timers.total_seconds[static_cast<int>(Stage::kMpm)] += 1e-3 * elapsed_ms;
    }
  }
  state->timers.calls[static_cast<int>(Stage::kPhysics)] += 1;
  report.substeps = model.substeps_per_control_step;
  state->frame_id += 1;
  state->episode_steps += 1;
  if (food) {
    state->timers.calls[static_cast<int>(Stage::kMpm)] += 1;
    const double inverse_count = 1.0 / model.substeps_per_control_step;
    food->contact_last_step = report.knife_contact;
    food->substeps_last_step = report.mpm_substeps;
    food->control_step_wrench = KnifeWrench{wrench_sum.force_n * inverse_count, wrench_sum.torque_nm * inverse_count};
    if (report.knife_contact && !food->first_contact_frame) {
      report.first_contact = true;
      food->first_contact_frame = state->frame_id;
      food->first_contact_time_s = static_cast<double>(state->episode_steps) * model.control_timestep_s;
    }
    if (model.food->topology_update && report.mpm_substeps > 0) {
      ScopedStageTimer timer(&state->timers, Stage::kTopology, &report.topology_wall_time_ms);
      UpdatePieces(*model.food, food);
    }
  }
  // Integer frame count times the timestep, so sim time never drifts by summation.
  state->sim_time_s = static_cast<double>(state->episode_steps) * model.control_timestep_s;
  report.truncated = model.config.max_episode_steps > 0 && state->episode_steps >= model.config.max_episode_steps;
  report.wall_time_ms = MillisecondsSince(start);
  return report;
}

}  // namespace culinarycut
