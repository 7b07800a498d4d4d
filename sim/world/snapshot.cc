#include "sim/world/snapshot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "sim/world/byte_stream.h"
#include "sim/world/state_fields.h"

namespace culinarycut {
namespace {

// The layout's version, bumped whenever the archived fields change (06: each cut's blade normals).
constexpr std::array<char, 8> kMagic = {'C', 'C', 'S', 'N', 'A', 'P', '0', '6'};

// Writes the fields in VisitState's order; optionally remembers where each field starts.
class SnapshotWriter {
 public:
  static constexpr bool kReading = false;
  explicit SnapshotWriter(std::vector<std::pair<std::size_t, std::string>>* field_offsets = nullptr)
      : field_offsets_(field_offsets) {}

  template <typename T>
  void Scalar(const char* name, T& value) {
    Mark(name);
    writer_.Put(value);
  }
  void Vector(const char* name, Eigen::VectorXd& value, std::size_t) {
    Mark(name);
    writer_.PutVector(value);
  }
  template <typename T>
  void Array(const char* name, std::vector<T>& values, std::size_t) {
    Mark(name);
    writer_.PutArray(values);
  }
  ByteWriter& bytes() { return writer_; }

 private:
  void Mark(const char* name) {
    if (field_offsets_) field_offsets_->emplace_back(writer_.size(), name);
  }
  ByteWriter writer_;
  std::vector<std::pair<std::size_t, std::string>>* field_offsets_;
};

// Reads the fields in VisitState's order, checking every length against the model.
class SnapshotReader {
 public:
  static constexpr bool kReading = true;
  explicit SnapshotReader(ByteReader* reader) : reader_(reader) {}

  template <typename T>
  void Scalar(const char*, T& value) {
    if constexpr (std::is_same_v<T, bool>) {
      value = reader_->Get<std::uint8_t>() != 0;  // any byte is a valid bool; a raw copy may not be
    } else {
      value = reader_->Get<T>();
    }
  }
  void Vector(const char* name, Eigen::VectorXd& value, std::size_t size) {
    value = reader_->GetVector(static_cast<std::uint32_t>(size), name);
  }
  template <typename T>
  void Array(const char* name, std::vector<T>& values, std::size_t size) {
    values = reader_->GetArray<T>(size, name);
  }

 private:
  ByteReader* reader_;
};

// Particles further than this from the world origin (m) are outside any scene: the table is 1.2 m
// by 1.6 m and the robot reaches under 1 m.
constexpr float kSceneHalfExtentM = 4.0f;

void Require(bool ok, const std::string& field, const std::string& problem) {
  if (!ok) throw SnapshotError("corrupt: " + field + " " + problem);
}

template <typename T>
bool AllFinite(const std::vector<T>& values) {
  for (const T value : values) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

// Refuses values no simulation could have produced, so a crafted snapshot cannot poison a session:
// every index in range, every number finite and physical, every counter consistent.
void CheckFood(const Model& model, const State& state) {
  const FoodState& food = *state.food;
  const mpm::Particles<float>& p = food.solver->particles();
  const std::size_t materials = model.food->solver->materials.size();
  const std::size_t objects = model.food->objects.size();
  for (int axis = 0; axis < 3; ++axis) {
    for (const float x : p.position[axis]) {
      Require(std::isfinite(x) && std::abs(x) <= kSceneHalfExtentM, "food.position",
              "holds a particle outside the scene (|x| > 4 m, or not finite)");
    }
    for (const float x : p.rest_position[axis]) {
      Require(std::isfinite(x) && std::abs(x) <= kSceneHalfExtentM, "food.rest_position",
              "holds a particle sampled outside the scene (|x| > 4 m, or not finite)");
    }
    for (const float v : p.velocity[axis]) {
      Require(std::isfinite(v) && std::abs(v) <= 2 * model.food->solver->config.max_particle_speed_m_s,
              "food.velocity", "holds a speed above the solver's cap, or not finite");
    }
  }
  for (int k = 0; k < 9; ++k) {
    Require(AllFinite(p.F[k]), "food.F", "is not finite");
    Require(AllFinite(p.C[k]), "food.C", "is not finite");
  }
  for (int k = 0; k < 6; ++k) Require(AllFinite(p.maxwell_stress[k]), "food.maxwell_stress", "is not finite");
  for (std::size_t i = 0; i < p.size(); ++i) {
    Require(std::isfinite(p.mass[i]) && p.mass[i] > 0, "food.mass", "must be finite and positive");
    Require(std::isfinite(p.volume[i]) && p.volume[i] > 0, "food.volume", "must be finite and positive");
    Require(std::isfinite(p.plastic_strain[i]) && p.plastic_strain[i] >= 0, "food.plastic_strain",
            "must be finite and >= 0");
    Require(p.damage[i] >= 0 && p.damage[i] <= 1, "food.damage", "must lie in [0, 1]");
    Require(p.piece[i] >= -1, "food.piece", "must be a label >= -1");
    Require(p.blade_side[i] >= -1 && p.blade_side[i] <= 1, "food.blade_side", "must be -1, 0 or 1");
    Require(mpm::ValidCutRecord(p.cut_sides[i]), "food.cut_sides", "sets a side for a cut the particle never passed");
    Require(p.material[i] < materials, "food.material", "indexes no material of the scene");
    Require(p.object[i] < objects, "food.object", "indexes no food object of the scene");
  }
  Require(food.knife_speed_factor > 0.0 && food.knife_speed_factor <= 1.0, "food.knife_speed_factor",
          "must lie in (0, 1]");
  for (const Eigen::Vector3d* v : {&food.wrench.force_n, &food.wrench.torque_nm, &food.control_step_wrench.force_n,
                                   &food.control_step_wrench.torque_nm}) {
    Require(v->allFinite(), "food.wrench", "is not finite");
  }
  Require(food.coupling_absorbed_j.allFinite(), "food.coupling_absorbed_j", "is not finite");
  Require(std::isfinite(food.quiet_time_s) && food.quiet_time_s >= 0, "food.quiet_time_s", "must be finite and >= 0");
  Require(std::isfinite(food.mpm_time_s) && food.mpm_time_s >= 0, "food.mpm_time_s", "must be finite and >= 0");
  Require(food.substeps_last_step >= 0, "food.substeps_last_step", "must be >= 0");
  Require(!food.first_contact_frame || *food.first_contact_frame <= state.frame_id, "food.first_contact_frame",
          "lies after the snapshot's frame");
  for (const mpm::Piece& piece : food.pieces) {
    Require(piece.object < objects, "food.pieces", "names no food object of the scene");
    Require(piece.particle_count <= p.size(), "food.pieces", "holds more particles than the food");
    Require(std::isfinite(piece.volume_m3) && std::isfinite(piece.mass_kg) && piece.centroid_m.allFinite() &&
                piece.bounds_m.min().allFinite() && piece.bounds_m.max().allFinite() &&
                piece.rest_bounds_m.min().allFinite() && piece.rest_bounds_m.max().allFinite(),
            "food.pieces", "holds a non-finite value");
  }
}

void CheckPlausible(const Model& model, const State& state) {
  // Frames and steps advance together from Reset, and sim time is their count times the period.
  Require(state.episode_steps == state.frame_id, "episode_steps", "differs from frame_id");
  Require(state.sim_time_s == static_cast<double>(state.episode_steps) * model.control_timestep_s, "sim_time_s",
          "is not episode_steps times the control period");
  // Contact can push a joint slightly past its limit; anything further is corruption.
  constexpr double kLimitToleranceRad = 0.1;
  const JointVector q = state.physics->JointPositions();
  const JointVector qdot = state.physics->JointVelocities();
  for (int i = 0; i < model.robot.dof(); ++i) {
    const JointLimits& limits = model.robot.limits[i];
    auto near_limits = [&limits](double angle_rad) {
      return std::isfinite(angle_rad) && angle_rad >= limits.lower_rad - kLimitToleranceRad &&
             angle_rad <= limits.upper_rad + kLimitToleranceRad;
    };
    const bool qdot_ok = std::isfinite(qdot[i]) && std::abs(qdot[i]) <= 10 * limits.max_velocity_rad_s;
    if (!near_limits(q[i]) || !near_limits(state.q_target_rad[i]) || !qdot_ok) {
      throw SnapshotError("corrupt: joint " + std::to_string(i) + " holds a non-finite or impossible value");
    }
  }
  if (state.food) CheckFood(model, state);
}

std::string Serialize(const Model& model, const State& state,
                      std::vector<std::pair<std::size_t, std::string>>* field_offsets = nullptr) {
  SnapshotWriter writer(field_offsets);
  writer.bytes().Put(kMagic);
  writer.bytes().Put(model.fingerprint);
  writer.bytes().Put(static_cast<std::uint8_t>(state.food != nullptr));
  // The writer only reads the fields; VisitState takes one signature for both directions.
  VisitState(writer, model, const_cast<State&>(state));
  return writer.bytes().Take();
}

}  // namespace

std::string SaveSnapshot(const Model& model, const State& state) { return Serialize(model, state); }

void RestoreSnapshot(const Model& model, const std::string& bytes, State* state) {
  ByteReader reader(bytes);
  if (reader.Get<std::array<char, 8>>() != kMagic) throw SnapshotError("not a CulinaryCut snapshot (bad header)");
  if (reader.Get<std::uint64_t>() != model.fingerprint) {
    throw SnapshotError("taken in a session with a different scene, or corrupt; restore it into a session "
                        "created from the same SceneSpec");
  }
  const bool has_food = reader.Get<std::uint8_t>() != 0;
  if (has_food != model.food.has_value()) throw SnapshotError("corrupt: food state does not match the scene");
  // Decode into a fresh state, so a bad snapshot changes nothing; a fresh world also means no
  // contact or solver cache from this session's past survives the restore.
  State restored;
  restored.physics = std::make_unique<PhysicsWorld>(model.robot, model.layout, model.physics_timestep_s);
  if (has_food) {
    restored.food = std::make_unique<FoodState>();
    ResetFood(*model.food, model.layout, restored.food.get());
  }
  SnapshotReader archive(&reader);
  VisitState(archive, model, restored);
  if (!reader.AtEnd()) throw SnapshotError("corrupt: trailing bytes");
  CheckPlausible(model, restored);
  *state = std::move(restored);
}

void CopyState(const Model& model, const State& from, State* to) { RestoreSnapshot(model, SaveSnapshot(model, from), to); }

std::string SaveStateButFoodBody(const Model& model, const State& state) {
  SnapshotWriter writer;
  VisitState(writer, model, const_cast<State&>(state), StateParts::kAllButFoodBody);
  return writer.bytes().Take();
}

std::string SaveFoodBody(const Model& model, const FoodState& food) {
  SnapshotWriter writer;
  state_fields_detail::VisitFoodBody(writer, model, const_cast<FoodState&>(food));
  return writer.bytes().Take();
}

void RestoreSavedParts(const Model& model, const std::string& state_but_food_body, const std::string* food_body,
                       State* state) {
  State restored;
  restored.physics = std::make_unique<PhysicsWorld>(model.robot, model.layout, model.physics_timestep_s);
  if (food_body) {
    restored.food = std::make_unique<FoodState>();
    ResetFood(*model.food, model.layout, restored.food.get());
    ByteReader body_bytes(*food_body);
    SnapshotReader body(&body_bytes);
    state_fields_detail::VisitFoodBody(body, model, *restored.food);
  } else {
    restored.food = std::move(state->food);  // untouched since it was saved: kept as it is
  }
  ByteReader rest_bytes(state_but_food_body);
  SnapshotReader rest(&rest_bytes);
  VisitState(rest, model, restored, StateParts::kAllButFoodBody);
  *state = std::move(restored);
}

std::optional<std::string> FirstStateDifference(const Model& model, const State& a, const State& b) {
  std::vector<std::pair<std::size_t, std::string>> fields;
  const std::string bytes_a = Serialize(model, a, &fields);
  const std::string bytes_b = Serialize(model, b);
  if (bytes_a == bytes_b) return std::nullopt;
  const std::size_t common = std::min(bytes_a.size(), bytes_b.size());
  std::size_t first = 0;
  while (first < common && bytes_a[first] == bytes_b[first]) ++first;
  std::string name = "snapshot header";
  for (const auto& [offset, field] : fields) {
    if (offset > first) break;
    name = field;
  }
  return name;
}

}  // namespace culinarycut
