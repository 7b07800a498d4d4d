#include "sim/world/state.h"

namespace culinarycut {

void ResetState(const Model& model, State* state, std::uint64_t seed, const std::vector<double>& initial_qpos_rad) {
  Eigen::VectorXd q = model.initial_qpos_rad;
  if (!initial_qpos_rad.empty()) {
    if (const auto error = CheckJointPositions(model.robot, initial_qpos_rad, "initial_qpos")) throw SceneError(*error);
    q = Eigen::Map<const Eigen::VectorXd>(initial_qpos_rad.data(), static_cast<long>(initial_qpos_rad.size()));
  }
  state->physics = std::make_unique<PhysicsWorld>(model.robot, model.layout, model.physics_timestep_s);
  state->physics->SetJointState(q, Eigen::VectorXd::Zero(q.size()));
  state->frame_id = 0;
  state->sim_time_s = 0.0;
  state->seed = seed;
  state->episode_steps = 0;
  state->q_target_rad = q;
  state->safety = safety::EpisodeSafety{};
  if (model.food) {
    if (!state->food) state->food = std::make_unique<FoodState>();
    ResetFood(*model.food, model.layout, state->food.get());
  }
}

}  // namespace culinarycut
