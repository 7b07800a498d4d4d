#include "sim/world/food_snapshot.h"

#include <cmath>

namespace culinarycut {
namespace {

// Calls `visit(array)` for every per-particle array, in one fixed order.
template <typename ParticlesT, typename Visit>
void ForEachParticleArray(ParticlesT& p, Visit&& visit) {
  for (auto& axis : p.position) visit(axis);
  for (auto& axis : p.velocity) visit(axis);
  for (auto& entry : p.F) visit(entry);
  for (auto& entry : p.C) visit(entry);
  visit(p.mass);
  visit(p.volume);
  visit(p.plastic_strain);
  visit(p.damage);
  visit(p.piece);
  visit(p.blade_side);
  visit(p.material);
  visit(p.object);
}

void WriteVector3(const Eigen::Vector3d& v, ByteWriter* writer) {
  for (int i = 0; i < 3; ++i) writer->Put(v[i]);
}

Eigen::Vector3d ReadVector3(ByteReader* reader) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = reader->Get<double>();
  if (!v.allFinite()) throw SnapshotError("corrupt: a non-finite food value");
  return v;
}

}  // namespace

void WriteFoodState(const FoodState& food, ByteWriter* writer) {
  const mpm::Solver<float>& solver = *food.solver;
  writer->Put(static_cast<std::uint64_t>(solver.particles().size()));
  ForEachParticleArray(solver.particles(), [writer](const auto& array) { writer->PutArray(array); });
  writer->Put(solver.substeps_taken());
  writer->Put(static_cast<std::uint8_t>(food.awake));
  writer->Put(food.quiet_time_s);
  writer->Put(food.substeps);
  writer->Put(food.mpm_time_s);
  WriteVector3(food.wrench.force_n, writer);
  WriteVector3(food.wrench.torque_nm, writer);
  WriteVector3(food.control_step_wrench.force_n, writer);
  WriteVector3(food.control_step_wrench.torque_nm, writer);
  writer->Put(food.knife_speed_factor);
  writer->Put(static_cast<std::uint8_t>(food.contact_last_step));
  writer->Put(static_cast<std::int32_t>(food.substeps_last_step));
  writer->Put(static_cast<std::uint8_t>(food.first_contact_frame.has_value()));
  writer->Put(food.first_contact_frame.value_or(0));
  writer->Put(food.first_contact_time_s.value_or(0.0));
  writer->Put(static_cast<std::uint32_t>(food.pieces.size()));
  for (const mpm::Piece& piece : food.pieces) {
    writer->Put(piece.label);
    writer->Put(piece.object);
    writer->Put(static_cast<std::uint64_t>(piece.particle_count));
    writer->Put(piece.volume_m3);
    writer->Put(piece.mass_kg);
    WriteVector3(piece.bounds_m.min(), writer);
    WriteVector3(piece.bounds_m.max(), writer);
    WriteVector3(piece.centroid_m, writer);
  }
}

std::unique_ptr<FoodState> ReadFoodState(const FoodModel& model, const SceneLayout& layout, ByteReader* reader) {
  auto food = std::make_unique<FoodState>();
  ResetFood(model, layout, food.get());  // colliders and materials as the model says
  mpm::Particles<float>& particles = food->solver->particles();
  const std::uint64_t count = reader->Get<std::uint64_t>();
  if (count != model.initial_particles.size()) throw SnapshotError("corrupt: wrong number of food particles");
  ForEachParticleArray(particles, [reader, count](auto& array) {
    using Value = typename std::decay_t<decltype(array)>::value_type;
    array = reader->GetArray<Value>(count);
  });
  for (int axis = 0; axis < 3; ++axis) {
    for (const float x : particles.position[axis]) {
      if (!std::isfinite(x)) throw SnapshotError("corrupt: a non-finite particle position");
    }
  }
  food->solver->RestoreSubstepsTaken(reader->Get<std::uint64_t>());
  food->awake = reader->Get<std::uint8_t>() != 0;
  food->quiet_time_s = reader->Get<double>();
  food->substeps = reader->Get<std::uint64_t>();
  food->mpm_time_s = reader->Get<double>();
  food->wrench.force_n = ReadVector3(reader);
  food->wrench.torque_nm = ReadVector3(reader);
  food->control_step_wrench.force_n = ReadVector3(reader);
  food->control_step_wrench.torque_nm = ReadVector3(reader);
  food->knife_speed_factor = reader->Get<double>();
  if (!(food->knife_speed_factor > 0.0 && food->knife_speed_factor <= 1.0)) {
    throw SnapshotError("corrupt: knife speed factor outside (0, 1]");
  }
  food->contact_last_step = reader->Get<std::uint8_t>() != 0;
  food->substeps_last_step = reader->Get<std::int32_t>();
  const bool has_contact = reader->Get<std::uint8_t>() != 0;
  const auto contact_frame = reader->Get<std::uint64_t>();
  const auto contact_time_s = reader->Get<double>();
  if (has_contact) {
    food->first_contact_frame = contact_frame;
    food->first_contact_time_s = contact_time_s;
  }
  const auto piece_count = reader->Get<std::uint32_t>();
  if (piece_count > count) throw SnapshotError("corrupt: more pieces than particles");
  food->pieces.clear();
  for (std::uint32_t i = 0; i < piece_count; ++i) {
    mpm::Piece piece;
    piece.label = reader->Get<std::int32_t>();
    piece.object = reader->Get<std::uint16_t>();
    piece.particle_count = reader->Get<std::uint64_t>();
    piece.volume_m3 = reader->Get<double>();
    piece.mass_kg = reader->Get<double>();
    const Eigen::Vector3d low = ReadVector3(reader);
    const Eigen::Vector3d high = ReadVector3(reader);
    piece.bounds_m = Eigen::AlignedBox3d(low, high);
    piece.centroid_m = ReadVector3(reader);
    food->pieces.push_back(piece);
  }
  food->particle_bounds = ParticleBounds(particles);
  return food;
}

}  // namespace culinarycut
