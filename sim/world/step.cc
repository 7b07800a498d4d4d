#include "sim/world/step.h"

#include <algorithm>

#include "sim/robot/kinematics.h"
#include "sim/world/food_step.h"
#include "sim/world/passive_coupling.h"
#include "sim/world/safety_stage.h"
#include "sim/world/step_rollback.h"

namespace culinarycut {
namespace {

Eigen::Isometry3d TcpInWorld(const Model& model, JointValues q_rad) {
  return model.robot_base_in_world * TipPose(model.robot, q_rad, model.tcp_in_last_link);
}

// Joint torques (N m) that put the food's wrench on the knife TCP: tau = J^T [f; t] (base frame),
// with `tcp_jacobian` the TCP's Jacobian at the joint positions now.
JointVector KnifeWrenchTorques(const Model& model, const Jacobian& tcp_jacobian, const KnifeWrench& wrench) {
  const Eigen::Matrix3d world_to_base = model.robot_base_in_world.linear().transpose();
  Eigen::Matrix<double, 6, 1> wrench_in_base;
  wrench_in_base << world_to_base * wrench.force_n, world_to_base * wrench.torque_nm;
  return tcp_jacobian.transpose() * wrench_in_base;
}

// Stage "apply action": the action becomes the joint targets the PD loop tracks.
void ApplyAction(const Model& model, const Action& action, State* state, StepResult* result) {
  JointTarget target = ComputeJointTarget(model, state->physics->JointPositions(), action);
  state->q_target_rad = target.q_target_rad;
  result->action_clipped = target.clipped;
  result->ik = target.ik;
}

// The knife TCP's linear velocity (m/s, world frame) from the joint velocities.
Eigen::Vector3d TcpVelocity(const Model& model, const Jacobian& tcp_jacobian, JointValues qdot_rad_s) {
  return model.robot_base_in_world.linear() * (tcp_jacobian.topRows<3>() * qdot_rad_s);
}

// Stage "robot", one physics step: the PD loop runs at the physics rate, a fresh velocity command
// every substep on top of gravity compensation (as the Panda's own controller does), so the servo
// only handles motion; nothing here allocates (the joint vectors hold their storage). With food, the
// food's force from the last physics step acts on the knife, kept passive (passive_coupling.h), and
// the speed resistance slows the servo while the knife is in the food (two-way coupling); `knife_axes`
// is the TCP's orientation now (world frame). Returns the force the knife felt (N, world frame).
Eigen::Vector3d AdvanceRobot(const Model& model, const Eigen::Matrix3d& knife_axes, State* state) {
  const Eigen::Vector3d gravity_in_base = model.robot_base_in_world.linear().transpose() * model.layout.gravity_m_s2;
  const JointVector q = state->physics->JointPositions();
  state->physics->AddJointTorques(GravityTorques(model.robot, q, gravity_in_base));
  JointVector qdot_command = JointVelocityCommand(model, q, state->q_target_rad);
  KnifeWrench felt;
  if (const FoodState* food = state->food.get()) {
    const Jacobian tcp_jacobian = TipJacobian(model.robot, q, model.tcp_in_last_link);
    felt.force_n = PassiveCouplingForce(food->wrench.force_n, knife_axes,
                                        TcpVelocity(model, tcp_jacobian, state->physics->JointVelocities()),
                                        model.physics_timestep_s, food->coupling_absorbed_j);
    felt.torque_nm = food->wrench.torque_nm;
    state->physics->AddJointTorques(KnifeWrenchTorques(model, tcp_jacobian, felt));
    qdot_command *= food->knife_speed_factor;
  }
  state->physics->SetJointVelocityCommand(qdot_command);
  state->physics->StepOnce();
  return felt.force_n;
}

// The knife's peak force and cutting speed this episode (the safety ablation's measures): the force
// over every physics step, the TCP's speed along its cutting direction (+z, edge first) in contact.
void RecordKnifePeaks(const Eigen::Isometry3d& tcp_start, const Eigen::Isometry3d& tcp_end, double timestep_s,
                      bool contact, const KnifeWrench& wrench, safety::EpisodeSafety* safety) {
  safety->peak_knife_force_n = std::max(safety->peak_knife_force_n, wrench.force_n.norm());
  if (!contact) return;
  const double cutting_speed_m_s =
      (tcp_end.translation() - tcp_start.translation()).dot(tcp_start.linear().col(2)) / timestep_s;
  safety->peak_cutting_speed_m_s = std::max(safety->peak_cutting_speed_m_s, cutting_speed_m_s);
}

// Stage "end of food step": contact bookkeeping over the control step, then piece detection.
// Runs before the clock advances: the first contact is dated to the frame this step ends on.
void EndFoodStep(const Model& model, const KnifeWrench& wrench_sum, State* state, StepResult* result) {
  FoodState* food = state->food.get();
  const double inverse_count = 1.0 / model.substeps_per_control_step;
  food->contact_last_step = result->knife_contact;
  food->substeps_last_step = result->mpm_substeps;
  food->control_step_wrench = KnifeWrench{wrench_sum.force_n * inverse_count, wrench_sum.torque_nm * inverse_count};
  if (result->knife_contact && !food->first_contact_frame) {
    result->first_contact = true;
    food->first_contact_frame = state->frame_id + 1;
    food->first_contact_time_s = static_cast<double>(state->episode_steps + 1) * model.control_timestep_s;
  }
  if (model.food->topology_update && result->mpm_substeps > 0) {
    StageClock clock(&result->timings, Stage::kTopology);
    UpdatePieces(*model.food, food);
  }
}

// Stage "task evaluation" (scenes with a task): ManiSkill's sparse reward, 1 while the task is done; success ends the
// episode (terminated).
void EvaluateStep(const Model& model, const State& state, StepResult* result) {
  result->task_score = EvaluateTask(*model.task, *model.food, MeasurePieces(*model.food, *state.food),
                                    state.food->solver->particles(),
                                    state.food->solver->cut_progress());
  result->success = result->task_score->success;
  result->reward = result->success ? 1.0 : 0.0;
  result->terminated = result->success;
}

// Stage "clock": the frame count, and sim time as an integer count times the timestep so it never
// drifts by summation; truncation at the episode's step limit.
void AdvanceClock(const Model& model, State* state, StepResult* result) {
  state->frame_id += 1;
  state->episode_steps += 1;
  state->sim_time_s = static_cast<double>(state->episode_steps) * model.control_timestep_s;
  result->truncated = model.config.max_episode_steps > 0 && state->episode_steps >= model.config.max_episode_steps;
}

}  // namespace

StepResult Step(const Model& model, State* state, const Action& action, const CancelCheck& cancelled,
                const ThreadLimit& thread_limit) {
  const auto start = std::chrono::steady_clock::now();
  StepResult result;
  // The state before the step, to put back if the step is cancelled half-way (the food's body saved
  // only once the step is about to change it).
  std::optional<StepRollback> rollback;
  if (cancelled) {
    StageClock clock(&result.timings, Stage::kRollback);
    rollback.emplace(model, *state);
  }
  // Runs inside the MPM stage's clock: its time moves from that stage to the rollback's.
  const std::function<void()> save_food_body = [&] {
    if (!rollback) return;
    const auto saving = std::chrono::steady_clock::now();
    rollback->BeforeFoodBodyChanges(*state->food);
    const double saving_ms = MillisecondsSince(saving);
    result.timings[Stage::kRollback] += saving_ms;
    result.timings[Stage::kMpm] -= saving_ms;
  };
  // Puts the state back as it was and marks the result, when the cancel check says stop.
  auto stop_here = [&] {
    if (!cancelled || !cancelled()) return false;
    rollback->Restore(state);
    result = StepResult{};
    result.cancelled = true;
    return true;
  };
  {
    StageClock clock(&result.timings, Stage::kControl);
    ApplyAction(model, action, state, &result);
  }
  if (model.limiter) {
    StageClock clock(&result.timings, Stage::kSafety);
    result.safety = LimitJointTarget(model, state);
  }
  FoodState* food = state->food.get();
  KnifeWrench wrench_sum;  // over the physics steps, for the control step's mean
  // The knife's pose at the start of each physics step is the pose at the end of the one before.
  Eigen::Isometry3d tcp_start = food ? TcpInWorld(model, state->physics->JointPositions()) : Eigen::Isometry3d::Identity();
  int saturated_in_contact = 0;  // physics steps with a motor at its effort limit, the knife in the food
  Eigen::Vector3d felt_force_n = Eigen::Vector3d::Zero();  // the food's force on the knife this physics step, as the arm felt it
  for (int i = 0; i < model.substeps_per_control_step; ++i) {
    if (stop_here()) return result;
    {
      StageClock clock(&result.timings, Stage::kPhysics);
      felt_force_n = AdvanceRobot(model, tcp_start.linear(), state);
    }
    if (!food) continue;
    StageClock clock(&result.timings, Stage::kMpm);
    if (thread_limit) food->solver->SetThreadLimit(thread_limit());
    const Eigen::Isometry3d tcp_end = TcpInWorld(model, state->physics->JointPositions());
    BookCouplingWork(felt_force_n, tcp_start.linear(), tcp_end.translation() - tcp_start.translation(),
                     &food->coupling_absorbed_j);
    const FoodStepReport food_report =
        AdvanceFood(*model.food, tcp_start, tcp_end, model.physics_timestep_s, food, cancelled, save_food_body);
    if (food_report.cancelled && stop_here()) return result;
    RecordKnifePeaks(tcp_start, tcp_end, model.physics_timestep_s, food_report.contact, food->wrench, &state->safety);
    tcp_start = tcp_end;
    result.mpm_substeps += food_report.substeps;
    result.knife_contact = result.knife_contact || food_report.contact;
    if (food_report.contact && state->physics->AnyMotorAtEffortLimit()) ++saturated_in_contact;
    wrench_sum.force_n += food->wrench.force_n;
    wrench_sum.torque_nm += food->wrench.torque_nm;
  }
  result.substeps = model.substeps_per_control_step;
  result.knife_stalled = result.knife_contact && 2 * saturated_in_contact >= model.substeps_per_control_step;
  if (food) EndFoodStep(model, wrench_sum, state, &result);
  if (model.task) {
    StageClock clock(&result.timings, Stage::kTask);
    EvaluateStep(model, *state, &result);
  }
  AdvanceClock(model, state, &result);
  // Asked once more at the end: a caller gone while the last substeps ran gets nothing applied.
  if (stop_here()) return result;
  result.wall_time_ms = MillisecondsSince(start);
  return result;
}

}  // namespace culinarycut
