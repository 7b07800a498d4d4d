#include "sim/world/observation.h"

#include "sim/robot/kinematics.h"
#include "sim/world/camera_observation.h"

namespace culinarycut {

RobotObservation ObserveRobot(const Model& model, const State& state) {
  RobotObservation observation;
  observation.qpos_rad = state.physics->JointPositions();
  observation.qvel_rad_s = state.physics->JointVelocities();
  observation.qpos_target_rad = state.q_target_rad;
  const Eigen::Isometry3d last_link = model.robot_base_in_world * ForwardKinematics(model.robot, observation.qpos_rad);
  observation.tcp_pose = PoseToVector(last_link * model.tcp_in_last_link);
  observation.flange_pose = PoseToVector(last_link * model.flange_in_last_link);
  observation.tcp_velocity = TipJacobian(model.robot, observation.qpos_rad, model.tcp_in_last_link) * observation.qvel_rad_s;
  if (state.food) {
    // The wrench acts at the TCP; moved to the flange origin and expressed in the flange frame.
    const Eigen::Isometry3d flange = last_link * model.flange_in_last_link;
    const Eigen::Vector3d tcp_from_flange_m = (last_link * model.tcp_in_last_link).translation() - flange.translation();
    const KnifeWrench& wrench = state.food->control_step_wrench;
    const Eigen::Matrix3d world_to_flange = flange.linear().transpose();
    observation.wrist_wrench << world_to_flange * wrench.force_n,
        world_to_flange * (wrench.torque_nm + tcp_from_flange_m.cross(wrench.force_n));
  }
  return observation;
}

Observation Observe(const Model& model, const State& state, render::CameraRenderer* renderer) {
  Observation observation;
  observation.frame_id = state.frame_id;
  observation.sim_time_s = state.sim_time_s;
  observation.robot = ObserveRobot(model, state);
  if (model.limiter) observation.safety = state.safety;
  if (state.food) {
    observation.food = FoodObservation{state.food->contact_last_step, state.food->substeps_last_step > 0,
                                       state.food->pieces};
  }
  if (model.task) {
    observation.instruction = model.task->instruction;
    observation.task_score = EvaluateTask(*model.task, *model.food, MeasurePieces(*model.food, *state.food),
                                            state.food->solver->particles(),
                                            state.food->solver->cut_progress());
  }
  if (renderer && !model.cameras.empty()) {
    StageTimes times;
    {
      StageClock clock(&times, Stage::kRender);
      observation.images = renderer->Render(MakeRenderScene(model, state), model.cameras);
    }
    observation.render_wall_time_ms = times[Stage::kRender];
  }
  return observation;
}

}  // namespace culinarycut
