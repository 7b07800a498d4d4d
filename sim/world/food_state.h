// The changing food part of a State: the MPM solver with its particles, whether it is awake, the
// wrench it puts on the knife, the pieces and the episode's contact bookkeeping.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/solver.h"
#include "sim/mpm/topology.h"
#include "sim/world/food_model.h"

namespace culinarycut {

// The force and torque the food exerts on the knife, world frame, torque about the knife TCP.
struct KnifeWrench {
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_nm = Eigen::Vector3d::Zero();
};

struct FoodState {
  std::unique_ptr<mpm::Solver<float>> solver;
  bool awake = false;                       // MPM substeps run only while awake
  double quiet_time_s = 0.0;                // how long the food has been at rest with the knife away
  std::uint64_t substeps = 0;               // MPM substeps this episode
  double mpm_time_s = 0.0;                  // simulated MPM time this episode
  KnifeWrench wrench;                       // mean over the last physics step
  KnifeWrench control_step_wrench;          // mean over the last control step (reported)
  double knife_speed_factor = 1.0;          // speed resistance of the last physics step, in (0, 1]
  // Work the arm has done on the food through the coupling minus what the food gave back, per knife
  // axis (along the blade, blade normal, cutting direction), J: what the food may still give back.
  Eigen::Vector3d coupling_absorbed_j = Eigen::Vector3d::Zero();
  bool contact_last_step = false;           // the knife touched the food during the last control step
  int substeps_last_step = 0;               // MPM substeps of the last control step
  std::optional<std::uint64_t> first_contact_frame;  // control step of the first knife-food contact
  std::optional<double> first_contact_time_s;
  std::vector<mpm::Piece> pieces;           // from the last topology update
  Eigen::AlignedBox3f particle_bounds;      // of all particles, after the last substep (m)
};

// A fresh episode: the model's initial particles at rest, the board and table colliders, the knife.
void ResetFood(const FoodModel& model, const SceneLayout& layout, FoodState* state);

// Bounding box of all particles (m).
Eigen::AlignedBox3f ParticleBounds(const mpm::Particles<float>& particles);

// Detects the pieces now (labels every particle's piece).
void UpdatePieces(const FoodModel& model, FoodState* state);

// The pieces the food is in now, for scoring the task: the last topology update's, or, with topology
// updates off (the paper's ablation: what is observed keeps its connectivity), detected on a copy of
// the particles so the observed labels stay as they were.
std::vector<mpm::Piece> MeasurePieces(const FoodModel& model, const FoodState& state);

}  // namespace culinarycut
