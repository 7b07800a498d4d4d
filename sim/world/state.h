// Everything that changes while a session runs (MuJoCo's mjData), and nothing else: no copies of
// Model data, no wall-clock timers (StepResult and Observation carry those). Its fields are listed
// once, in state_fields.h, which drives snapshot, restore, copy and comparison.
#pragma once

#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "sim/safety/limiter.h"
#include "sim/world/food_state.h"
#include "sim/world/model.h"
#include "sim/world/physics_world.h"

namespace culinarycut {

struct State {
  std::unique_ptr<PhysicsWorld> physics;  // null until the first Reset
  std::uint64_t frame_id = 0;             // 0 after Reset, +1 per Step
  double sim_time_s = 0.0;
  std::uint64_t seed = 0;                 // the episode's seed, as Reset was given it
  std::uint32_t episode_steps = 0;
  Eigen::VectorXd q_target_rad;           // what the joint PD controller tracks
  std::unique_ptr<FoodState> food;        // only when the model has food
  safety::EpisodeSafety safety;           // the limiter's interventions, the knife's peak force and speed

  bool has_been_reset() const { return physics != nullptr; }
};

// Starts a new episode: rebuilds the physics world and puts the robot at rest at `initial_qpos`
// (the model's when empty). Throws SceneError when initial_qpos is out of range.
void ResetState(const Model& model, State* state, std::uint64_t seed, const std::vector<double>& initial_qpos_rad);

}  // namespace culinarycut
