#include "sim/world/snapshot.h"

#include <array>
#include <cmath>
#include <cstring>
#include <sstream>

namespace culinarycut {
namespace {

constexpr std::array<char, 8> kMagic = {'C', 'C', 'S', 'N', 'A', 'P', '0', '1'};

class Writer {
 public:
  template <typename T>
  void Put(const T& value) { bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T)); }
  void PutVector(const Eigen::VectorXd& v) {
    Put(static_cast<std::uint32_t>(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), sizeof(double) * v.size());
  }
  void PutString(const std::string& s) {
    Put(static_cast<std::uint32_t>(s.size()));
    bytes_.append(s);
  }
  std::string Take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T Get() {
    Need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  Eigen::VectorXd GetVector(std::uint32_t expected_size) {
    const auto size = Get<std::uint32_t>();
    if (size != expected_size) throw SnapshotError("corrupt: a joint vector has the wrong length");
    Eigen::VectorXd v(size);
    Need(sizeof(double) * size);
    std::memcpy(v.data(), bytes_.data() + offset_, sizeof(double) * size);
    offset_ += sizeof(double) * size;
    return v;
  }
  std::string GetString() {
    const auto size = Get<std::uint32_t>();
    Need(size);
    std::string s = bytes_.substr(offset_, size);
    offset_ += size;
    return s;
  }
  bool AtEnd() const { return offset_ == bytes_.size(); }

 private:
  void Need(size_t n) const {
    if (offset_ + n > bytes_.size()) throw SnapshotError("snapshot is truncated");
  }
  const std::string& bytes_;
  size_t offset_ = 0;
};

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
  Writer writer;
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
  return writer.Take();
}

void RestoreSnapshot(const Model& model, const std::string& bytes, State* state) {
  Reader reader(bytes);
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
}

}  // namespace culinarycut
