#include "sim/world/snapshot.h"

#include "sim/world/byte_stream.h"
#include "sim/world/food_snapshot.h"

#include <array>
#include <cmath>
#include <cstring>
#include <sstream>

namespace culinarycut {
namespace {

constexpr std::array<char, 8> kMagic = {'C', 'C', 'S', 'N', 'A', 'P', '0', '2'};

// Refuses values no simulation could have produced, so a corrupted snapshot cannot poison a session.
void CheckPlausible(const Model& model, double sim_time_s, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot,
                    const Eigen::VectorXd& q_target) {
  // Contact can push a joint slightly past its limit; anything further is corruption.
  constexpr double kLimitToleranceRad = 0.1;
  if (!std::isfinite(sim_time_s) || sim_time_s < 0) throw SnapshotError("corrupt: bad sim time");
  for (int i = 0; i < model.robot.dof(); ++i) {
    const JointLimits& limits = model.robot.limits[i];
    auto near_limits = [&limits](double angle_rad) {
      return std::isfinite(angle_rad) && angle_rad >= limits.lower_rad - kLimitToleranceRad &&
             angle_rad <= limits.upper_rad + kLimitToleranceRad;
    };
    const bool qdot_ok = std::isfinite(qdot[i]) && std::abs(qdot[i]) <= 10 * limits.max_velocity_rad_s;
    if (!near_limits(q[i]) || !near_limits(q_target[i]) || !qdot_ok) {
      throw SnapshotError("corrupt: joint " + std::to_string(i) + " holds a non-finite or impossible value");
    }
  }
}

}  // namespace

std::string SaveSnapshot(const Model& model, const State& state) {
  ByteWriter writer;
  writer.Put(kMagic);
  writer.Put(model.fingerprint);
  writer.Put(state.frame_id);
  writer.Put(state.sim_time_s);
  writer.Put(state.seed);
  writer.Put(state.episode_steps);
  std::ostringstream rng;
  rng << state.rng;
  writer.PutString(rng.str());
  writer.PutVector(state.physics->JointPositions());
  writer.PutVector(state.physics->JointVelocities());
  writer.PutVector(state.q_target_rad);
  writer.Put(static_cast<std::uint8_t>(state.food != nullptr));
  if (state.food) WriteFoodState(*state.food, &writer);
  return writer.Take();
}

void RestoreSnapshot(const Model& model, const std::string& bytes, State* state) {
  ByteReader reader(bytes);
  if (reader.Get<std::array<char, 8>>() != kMagic) throw SnapshotError("not a CulinaryCut snapshot (bad header)");
  if (reader.Get<std::uint64_t>() != model.fingerprint) {
    throw SnapshotError("taken in a session with a different scene, or corrupt; restore it into a session "
                        "created from the same SceneSpec");
  }
  // Decode everything before touching the state, so a bad snapshot changes nothing.
  const auto dof = static_cast<std::uint32_t>(model.robot.dof());
  const auto frame_id = reader.Get<std::uint64_t>();
  const auto sim_time = reader.Get<double>();
  const auto seed = reader.Get<std::uint64_t>();
  const auto episode_steps = reader.Get<std::uint32_t>();
  std::istringstream rng_text(reader.GetString());
  std::mt19937_64 rng;
  rng_text >> rng;
  if (rng_text.fail()) throw SnapshotError("corrupt: bad random-generator state");
  const Eigen::VectorXd q = reader.GetVector(dof);
  const Eigen::VectorXd qdot = reader.GetVector(dof);
  const Eigen::VectorXd q_target = reader.GetVector(dof);
  const bool has_food = reader.Get<std::uint8_t>() != 0;
  if (has_food != model.food.has_value()) throw SnapshotError("corrupt: food state does not match the scene");
  std::unique_ptr<FoodState> food = has_food ? ReadFoodState(*model.food, model.layout, &reader) : nullptr;
  if (!reader.AtEnd()) throw SnapshotError("corrupt: trailing bytes");
  CheckPlausible(model, sim_time, q, qdot, q_target);

  // A fresh world: no contact or solver cache from this session's past survives the restore.
  auto physics = std::make_unique<PhysicsWorld>(model.robot, model.layout, model.physics_timestep_s);
  physics->SetJointState(q, qdot);
  state->physics = std::move(physics);
  state->frame_id = frame_id;
  state->sim_time_s = sim_time;
  state->seed = seed;
  state->episode_steps = episode_steps;
  state->rng = rng;
  state->q_target_rad = q_target;
  state->food = std::move(food);
}

}  // namespace culinarycut
