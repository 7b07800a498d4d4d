#include "server/wire/observation.h"

#include <algorithm>
#include <cmath>

#include "server/wire/camera.h"
#include "server/wire/task.h"
#include "server/wire/values.h"
#include "sim/world/control_mode.h"

namespace culinarycut::server {
namespace {

// An unbounded vector observation (empty low/high on the wire means unbounded), float32 as in
// ManiSkill; the values travel as doubles.
v1::ArraySpec* AddArraySpec(v1::CreateSessionResponse* response, const std::string& name, int size,
                            const std::string& description) {
  v1::ArraySpec* spec = response->add_observation_spec();
  spec->set_name(name);
  spec->add_shape(size);
  spec->set_dtype("float32");
  spec->set_description(description);
  return spec;
}

void FoodObservationToWire(const FoodObservation& food, v1::FoodObservation* wire) {
  wire->set_knife_contact(food.knife_contact);
  wire->set_mpm_awake(food.mpm_awake);
  for (const mpm::Piece& piece : food.pieces) {
    v1::FoodPiece* out = wire->add_pieces();
    out->set_object(piece.object);
    out->set_particles(static_cast<std::uint32_t>(piece.particle_count));
    out->set_volume(piece.volume_m3);
    AssignVector(piece.centroid_m, out->mutable_centroid());
    AssignVector(piece.bounds_m.min(), out->mutable_bounds_min());
    AssignVector(piece.bounds_m.max(), out->mutable_bounds_max());
  }
}

void SafetyStepToWire(const safety::LimiterReport& report, v1::SafetyStepInfo* wire) {
  wire->set_acted(report.acted);
  for (int i = 0; i < safety::kGuardCount; ++i) (*wire->mutable_guard_counts())[safety::kGuardNames[i]] = report.guard_counts[i];
  wire->set_reason(report.reason);
  // NaN in the engine means no food was near the edge; the wire says so with `assessed`.
  wire->set_assessed(std::isfinite(report.v_safe_m_s));
  if (wire->assessed()) {
    wire->set_v_safe_m_s(report.v_safe_m_s);
    wire->set_predicted_force_n(report.predicted_force_n);
  }
  wire->set_out_of_range(report.out_of_range);
  wire->set_commanded_speed_m_s(report.commanded_speed_m_s);
  wire->set_target_scale(report.target_scale);
}


}  // namespace

void StampToWire(std::uint64_t frame_id, double sim_time_s, v1::FrameStamp* wire) {
  wire->set_frame_id(frame_id);
  wire->set_sim_time(sim_time_s);
}

void ObservationToWire(const Model& model, const Observation& observation, v1::Observation* wire) {
  const RobotObservation& robot = observation.robot;
  v1::AgentObservation* agent = wire->mutable_agent();
  AssignVector(robot.qpos_rad, agent->mutable_qpos());
  AssignVector(robot.qvel_rad_s, agent->mutable_qvel());
  AssignVector(robot.qpos_target_rad, agent->mutable_qpos_target());
  AssignVector(robot.tcp_pose, wire->mutable_tcp_pose());
  AssignVector(robot.tcp_velocity, wire->mutable_tcp_velocity());
  AssignVector(robot.flange_pose, wire->mutable_flange_pose());
  AssignVector(robot.wrist_wrench, wire->mutable_wrist_wrench());
  if (observation.food) FoodObservationToWire(*observation.food, wire->mutable_food());
  if (!observation.instruction.empty()) wire->set_instruction(observation.instruction);
  CameraImagesToWire(model, observation.images, wire);
}

void StepResultToWire(const StepResult& result, double render_wall_time_ms, v1::StepResponse* wire) {
  wire->set_reward(result.reward);
  wire->set_terminated(result.terminated);
  wire->set_truncated(result.truncated);
  if (result.task_score) TaskScoreToWire(*result.task_score, wire->mutable_task_score());
  v1::StepInfo* info = wire->mutable_info();
  info->set_substeps(static_cast<std::uint32_t>(result.substeps));
  info->set_action_clipped(result.action_clipped);
  if (result.ik) {
    info->set_ik_converged(result.ik->converged);
    info->set_ik_position_error(result.ik->position_error_m);
    info->set_ik_orientation_error(result.ik->orientation_error_rad);
  }
  info->set_mpm_substeps(static_cast<std::uint32_t>(result.mpm_substeps));
  info->set_first_contact(result.first_contact);
  info->set_knife_stalled(result.knife_stalled);
  info->set_step_wall_time_ms(result.wall_time_ms);
  info->set_control_wall_time_ms(result.timings[Stage::kControl]);
  info->set_physics_wall_time_ms(result.timings[Stage::kPhysics]);
  info->set_mpm_wall_time_ms(result.timings[Stage::kMpm]);
  info->set_topology_wall_time_ms(result.timings[Stage::kTopology]);
  info->set_safety_wall_time_ms(result.timings[Stage::kSafety]);
  info->set_rollback_wall_time_ms(result.timings[Stage::kRollback]);
  if (result.safety) SafetyStepToWire(*result.safety, info->mutable_safety());
  info->set_render_wall_time_ms(render_wall_time_ms);
}

void SessionStatsToWire(const Model& model, const State& state, const StageTotals& totals, v1::SessionStats* wire) {
  StampToWire(state.frame_id, state.sim_time_s, wire->mutable_stamp());
  wire->set_mpm_allocated(state.food != nullptr && state.food->solver != nullptr);
  if (model.food) {
    wire->set_mpm_dx(model.food->resolution.dx_m);
    wire->set_mpm_particles_per_cell(model.food->resolution.particles_per_cell);
    wire->set_mpm_cfl(model.food->resolution.cfl);
  }
  if (state.food && state.food->solver) {
    const mpm::Particles<float>& particles = state.food->solver->particles();
    wire->set_mpm_particles(particles.size());
    if (model.food->solver->config.activity.radius_m > 0.0) {
      wire->set_mpm_frozen_particles(std::count(particles.activity.begin(), particles.activity.end(), mpm::kFrozen));
    }
    wire->set_mpm_substeps(state.food->substeps);
    wire->set_has_contact(state.food->first_contact_frame.has_value());
    wire->set_first_contact_frame(state.food->first_contact_frame.value_or(0));
    v1::SafetyTotals* safety = wire->mutable_safety();
    safety->set_peak_knife_force_n(state.safety.peak_knife_force_n);
    safety->set_peak_cutting_speed_m_s(state.safety.peak_cutting_speed_m_s);
    if (model.limiter) {
      for (int i = 0; i < safety::kGuardCount; ++i) {
        (*safety->mutable_interventions())[safety::kGuardNames[i]] = state.safety.interventions[i];
      }
    }
  }
  for (int stage = 0; stage < kStageCount; ++stage) {
    (*wire->mutable_stage_wall_time_s())[kStageNames[stage]] = totals.wall_s[stage];
    (*wire->mutable_stage_calls())[kStageNames[stage]] = totals.calls[stage];
  }
}

v1::TelemetryFrame TelemetryToWire(const Observation& observation, const safety::LimiterReport* step_report) {
  v1::TelemetryFrame frame;  // no session id: the topic it is published under tells sessions apart
  StampToWire(observation.frame_id, observation.sim_time_s, frame.mutable_stamp());
  AssignVector(observation.robot.qpos_rad, frame.mutable_qpos());
  AssignVector(observation.robot.qvel_rad_s, frame.mutable_qvel());
  AssignVector(observation.robot.tcp_pose, frame.mutable_tcp_pose());
  AssignVector(observation.robot.wrist_wrench, frame.mutable_wrist_wrench());
  // NaN in the engine means no food was near the edge: not assessed.
  if (observation.safety && std::isfinite(observation.safety->v_safe_m_s)) {
    frame.set_assessed(true);
    frame.set_v_safe_m_s(observation.safety->v_safe_m_s);
    frame.set_predicted_force_n(observation.safety->predicted_force_n);
  }
  if (step_report) {
    frame.set_limiter_acted(step_report->acted);
    for (int i = 0; i < safety::kGuardCount; ++i) {
      if (step_report->guard_counts[i] > 0) frame.add_bound_guards(safety::kGuardNames[i]);
    }
  }
  return frame;
}

void DescribeSpaces(const Model& model, v1::CreateSessionResponse* response) {
  const int dof = model.robot.dof();
  v1::ArraySpec* qpos = AddArraySpec(response, "agent/qpos", dof, "joint angles q1..q7 (rad)");
  for (const JointLimits& limits : model.robot.limits) {
    qpos->add_low(limits.lower_rad);
    qpos->add_high(limits.upper_rad);
  }
  AddArraySpec(response, "agent/qvel", dof, "joint velocities (rad/s)");
  AddArraySpec(response, "agent/qpos_target", dof, "joint targets of the PD controller (rad)");
  AddArraySpec(response, "extra/tcp_pose", 7, "knife TCP [x, y, z] (m) and [qw, qx, qy, qz], world frame");
  AddArraySpec(response, "extra/tcp_velocity", 6, "knife TCP [vx, vy, vz] (m/s), [wx, wy, wz] (rad/s), world");
  AddArraySpec(response, "extra/flange_pose", 7, "flange [x, y, z] (m) and [qw, qx, qy, qz], world frame");
  AddArraySpec(response, "extra/wrist_wrench", 6,
               "food on knife at the flange, flange frame: [fx, fy, fz] (N), [tx, ty, tz] (N m); zeros without food");

  DescribeCameraSpaces(model, response);

  for (ControlMode mode : AllControlModes()) {
    const ActionBounds bounds = ActionBoundsFor(model, mode);
    v1::ControlModeSpec* spec = response->add_control_modes();
    spec->set_name(ControlModeName(mode));
    v1::ArraySpec* action = spec->mutable_action();
    action->set_name("action");
    action->add_shape(static_cast<std::uint32_t>(bounds.low.size()));
    action->set_dtype("float32");  // ManiSkill's action spaces; the values travel as doubles
    action->mutable_low()->Assign(bounds.low.begin(), bounds.low.end());
    action->mutable_high()->Assign(bounds.high.begin(), bounds.high.end());
    action->set_description(bounds.description);
  }
  response->set_default_control_mode(ControlModeName(kDefaultControlMode));
  response->set_control_timestep(model.control_timestep_s);
}

}  // namespace culinarycut::server
