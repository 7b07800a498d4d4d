#include "sim/world/step.h"

#include <chrono>

#include "sim/robot/kinematics.h"

namespace culinarycut {

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
  {
    ScopedStageTimer timer(&state->timers, Stage::kPhysics, &report.physics_wall_time_ms);
    // The PD loop runs at the physics rate: a fresh velocity command every substep, on top of
    // gravity compensation (as the Panda's own controller does), so the servo only handles motion.
    const Eigen::Vector3d gravity_in_base = model.robot_base_in_world.linear().transpose() * model.layout.gravity_m_s2;
    for (int i = 0; i < model.substeps_per_control_step; ++i) {
      const Eigen::VectorXd q = state->physics->JointPositions();
      state->physics->AddJointTorques(GravityTorques(model.robot, q, gravity_in_base));
      state->physics->SetJointVelocityCommand(JointVelocityCommand(model, q, state->q_target_rad));
      state->physics->StepOnce();
    }
  }
  report.substeps = model.substeps_per_control_step;
  state->frame_id += 1;
  state->episode_steps += 1;
  // Integer frame count times the timestep, so sim time never drifts by summation.
  state->sim_time_s = static_cast<double>(state->episode_steps) * model.control_timestep_s;
  report.truncated = model.config.max_episode_steps > 0 && state->episode_steps >= model.config.max_episode_steps;
  report.wall_time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace culinarycut
