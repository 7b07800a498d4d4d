// The one list of a State's fields, in one fixed order. Snapshot (write), restore (read), copy and
// the field-by-field comparison tests use all walk it, so a new field is added here and nowhere
// else. An Archive has `static constexpr bool kReading` and three methods, each taking a field name
// (for error messages and comparisons) and the field:
//   Scalar(name, T&)                      a plain value (integer, float, bool, enum)
//   Vector(name, Eigen::VectorXd&, size)  a joint vector of exactly `size` entries
//   Array(name, std::vector<T>&, size)    a per-particle array of exactly `size` entries
// Fields that live behind an interface (the Bullet world's joint state, the solver's substep
// count) go through a local copy: written from the object, or read into it afterwards.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

namespace state_fields_detail {

template <typename Archive>
void VisitVector3(Archive& archive, const std::string& name, Eigen::Vector3d& v) {
  archive.Scalar((name + ".x").c_str(), v.x());
  archive.Scalar((name + ".y").c_str(), v.y());
  archive.Scalar((name + ".z").c_str(), v.z());
}

template <typename Archive>
void VisitWrench(Archive& archive, const std::string& name, KnifeWrench& wrench) {
  VisitVector3(archive, name + ".force_n", wrench.force_n);
  VisitVector3(archive, name + ".torque_nm", wrench.torque_nm);
}

template <typename Archive, typename ParticlesT>
void VisitParticles(Archive& archive, ParticlesT& p, std::size_t count) {
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) archive.Array((std::string("food.position.") + kAxes[axis]).c_str(), p.position[axis], count);
  for (int axis = 0; axis < 3; ++axis) archive.Array((std::string("food.velocity.") + kAxes[axis]).c_str(), p.velocity[axis], count);
  for (int axis = 0; axis < 3; ++axis) {
    archive.Array((std::string("food.rest_position.") + kAxes[axis]).c_str(), p.rest_position[axis], count);
  }
  for (int k = 0; k < 9; ++k) archive.Array(("food.F[" + std::to_string(k) + "]").c_str(), p.F[k], count);
  for (int k = 0; k < 9; ++k) archive.Array(("food.C[" + std::to_string(k) + "]").c_str(), p.C[k], count);
  archive.Array("food.mass", p.mass, count);
  archive.Array("food.volume", p.volume, count);
  archive.Array("food.plastic_strain", p.plastic_strain, count);
  for (int k = 0; k < 6; ++k) {
    archive.Array(("food.maxwell_stress[" + std::to_string(k) + "]").c_str(), p.maxwell_stress[k], count);
  }
  archive.Array("food.damage", p.damage, count);
  archive.Array("food.piece", p.piece, count);
  archive.Array("food.blade_side", p.blade_side, count);
  archive.Array("food.cut_sides", p.cut_sides, count);
  archive.Array("food.material", p.material, count);
  archive.Array("food.object", p.object, count);
  archive.Array("food.activity", p.activity, count);
}

template <typename Archive>
void VisitPiece(Archive& archive, const std::string& name, mpm::Piece& piece) {
  archive.Scalar((name + ".label").c_str(), piece.label);
  archive.Scalar((name + ".object").c_str(), piece.object);
  archive.Scalar((name + ".particle_count").c_str(), piece.particle_count);
  archive.Scalar((name + ".volume_m3").c_str(), piece.volume_m3);
  archive.Scalar((name + ".mass_kg").c_str(), piece.mass_kg);
  Eigen::Vector3d low = piece.bounds_m.min(), high = piece.bounds_m.max();
  VisitVector3(archive, name + ".bounds_min_m", low);
  VisitVector3(archive, name + ".bounds_max_m", high);
  if constexpr (Archive::kReading) piece.bounds_m = Eigen::AlignedBox3d(low, high);
  Eigen::Vector3d rest_low = piece.rest_bounds_m.min(), rest_high = piece.rest_bounds_m.max();
  VisitVector3(archive, name + ".rest_bounds_min_m", rest_low);
  VisitVector3(archive, name + ".rest_bounds_max_m", rest_high);
  if constexpr (Archive::kReading) piece.rest_bounds_m = Eigen::AlignedBox3d(rest_low, rest_high);
  VisitVector3(archive, name + ".centroid_m", piece.centroid_m);
}

// The food's body: its particles, the solver's counters, the cuts and the pieces; a step changes
// it only while the food is awake. Precondition when reading: `food` was reset from the model
// (solver built, colliders placed).
template <typename Archive>
void VisitFoodBody(Archive& archive, const Model& model, FoodState& food) {
  const std::size_t count = model.food->initial_particles.size();
  VisitParticles(archive, food.solver->particles(), count);
  std::uint64_t solver_substeps = food.solver->substeps_taken();  // decides the next reordering
  archive.Scalar("food.solver_substeps", solver_substeps);
  if constexpr (Archive::kReading) food.solver->RestoreSubstepsTaken(solver_substeps);
  mpm::CutProgress cuts = food.solver->cut_progress();
  archive.Scalar("food.cuts.made", cuts.cuts_made);
  archive.Scalar("food.cuts.current", cuts.current);
  archive.Scalar("food.cuts.blade_in_food", cuts.blade_in_food);
  // Each cut's blade normal moment: the six distinct entries of the symmetric sum, then its duration.
  constexpr std::size_t kMomentValues = 7;
  std::vector<double> moments(kMomentValues * mpm::kMaxRecordedCuts);
  for (std::size_t cut = 0; cut < cuts.blade_normals.size(); ++cut) {
    const mpm::BladeNormalMoment& moment = cuts.blade_normals[cut];
    const Eigen::Matrix3d& m = moment.normal_outer_s;
    const double values[kMomentValues] = {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2), moment.duration_s};
    std::copy(values, values + kMomentValues, moments.begin() + kMomentValues * cut);
  }
  archive.Array("food.cuts.blade_normals", moments, moments.size());
  if constexpr (Archive::kReading) {
    for (std::size_t cut = 0; cut < cuts.blade_normals.size(); ++cut) {
      const double* v = moments.data() + kMomentValues * cut;
      Eigen::Matrix3d& m = cuts.blade_normals[cut].normal_outer_s;
      m << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
      cuts.blade_normals[cut].duration_s = v[6];
    }
  }
  if constexpr (Archive::kReading) {
    try {
      food.solver->RestoreCutProgress(cuts);
    } catch (const std::invalid_argument& error) {
      throw SnapshotError(std::string("food.cuts: ") + error.what());
    }
  }
  std::uint64_t piece_count = food.pieces.size();
  archive.Scalar("food.piece_count", piece_count);
  if constexpr (Archive::kReading) {
    if (piece_count > count) throw SnapshotError("food.piece_count: more pieces than particles");
    food.pieces.assign(piece_count, mpm::Piece{});
  }
  for (std::size_t i = 0; i < food.pieces.size(); ++i) {
    VisitPiece(archive, "food.pieces[" + std::to_string(i) + "]", food.pieces[i]);
  }
  if constexpr (Archive::kReading) food.particle_bounds = ParticleBounds(food.solver->particles());
}


// The food's few scalars (sleep, wrenches, contact), which a step may change while the food sleeps.
template <typename Archive>
void VisitFoodScalars(Archive& archive, FoodState& food) {
  archive.Scalar("food.awake", food.awake);
  archive.Scalar("food.quiet_time_s", food.quiet_time_s);
  archive.Scalar("food.substeps", food.substeps);
  archive.Scalar("food.mpm_time_s", food.mpm_time_s);
  VisitWrench(archive, "food.wrench", food.wrench);
  VisitWrench(archive, "food.control_step_wrench", food.control_step_wrench);
  archive.Scalar("food.knife_speed_factor", food.knife_speed_factor);
  VisitVector3(archive, "food.coupling_absorbed_j", food.coupling_absorbed_j);
  archive.Scalar("food.contact_last_step", food.contact_last_step);
  archive.Scalar("food.substeps_last_step", food.substeps_last_step);
  bool has_contact = food.first_contact_frame.has_value();
  std::uint64_t contact_frame = food.first_contact_frame.value_or(0);
  double contact_time_s = food.first_contact_time_s.value_or(0.0);
  archive.Scalar("food.has_first_contact", has_contact);
  archive.Scalar("food.first_contact_frame", contact_frame);
  archive.Scalar("food.first_contact_time_s", contact_time_s);
  if constexpr (Archive::kReading) {
    food.first_contact_frame = has_contact ? std::optional<std::uint64_t>(contact_frame) : std::nullopt;
    food.first_contact_time_s = has_contact ? std::optional<double>(contact_time_s) : std::nullopt;
  }
}

template <typename Archive>
void VisitSafety(Archive& archive, safety::EpisodeSafety& safety) {
  for (int i = 0; i < safety::kGuardCount; ++i) {
    archive.Scalar((std::string("safety.interventions.") + safety::kGuardNames[i]).c_str(), safety.interventions[i]);
  }
  archive.Scalar("safety.peak_knife_force_n", safety.peak_knife_force_n);
  archive.Scalar("safety.peak_cutting_speed_m_s", safety.peak_cutting_speed_m_s);
  archive.Scalar("safety.v_safe_m_s", safety.v_safe_m_s);
  archive.Scalar("safety.predicted_force_n", safety.predicted_force_n);
  archive.Scalar("safety.out_of_range", safety.out_of_range);
}

}  // namespace state_fields_detail

// Walks every field of a reset `state` (for reading: a state whose physics world and food were
// just built from `model`, see snapshot.cc). Writing archives only read the fields.
// A whole state, or all of it but the food's body (for Step's rollback, which saves the body apart).
enum class StateParts { kAll, kAllButFoodBody };

template <typename Archive>
void VisitState(Archive& archive, const Model& model, State& state, StateParts parts = StateParts::kAll) {
  const auto dof = static_cast<std::size_t>(model.robot.dof());
  archive.Scalar("frame_id", state.frame_id);
  archive.Scalar("sim_time_s", state.sim_time_s);
  archive.Scalar("seed", state.seed);
  archive.Scalar("episode_steps", state.episode_steps);
  state_fields_detail::VisitSafety(archive, state.safety);
  Eigen::VectorXd q = state.physics->JointPositions();
  Eigen::VectorXd qdot = state.physics->JointVelocities();
  archive.Vector("robot.qpos_rad", q, dof);
  archive.Vector("robot.qvel_rad_s", qdot, dof);
  if constexpr (Archive::kReading) state.physics->SetJointState(q, qdot);
  archive.Vector("robot.q_target_rad", state.q_target_rad, dof);
  if (!state.food) return;
  if (parts == StateParts::kAll) state_fields_detail::VisitFoodBody(archive, model, *state.food);
  state_fields_detail::VisitFoodScalars(archive, *state.food);
}

}  // namespace culinarycut
