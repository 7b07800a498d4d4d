// Runs a compiled cut substep by substep: the knife follows its path, each substep's diagnostics go
// to a callback, and the summary holds what came out (pieces, cut positions, forces, momentum
// balance, timings).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/materials.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/topology.h"
#include "tools/cc_cut/cut_model.h"

namespace culinarycut::cc_cut {

// One substep as the callback sees it.
struct CutStepRecord {
  int step = 0;                 // 0, 1, ...
  double time_s = 0.0;          // simulated time at the end of this substep
  double knife_height_m = 0.0;  // edge (TCP) height during this substep
  mpm::SubstepDiagnostics diagnostics;
};
using CutStepCallback = std::function<void(const CutStepRecord&)>;

// Where each particle ended up: where it was sampled (material coordinates, m), where it is now (m)
// and its piece (-1: a crumb or broken). The accuracy study compares pieces' final shapes with it.
struct FinalParticles {
  std::array<std::vector<float>, 3> rest_position_m;
  std::array<std::vector<float>, 3> position_m;
  std::vector<std::int32_t> piece;
};

struct CutSummary {
  // What the scene resolved to.
  mpm::Material material;
  double dt_s = 0.0;      // substep length for sound and the knife (s)
  std::size_t particles = 0;
  double food_length_m = 0.0;                               // along the long axis
  Eigen::Vector3d axis_origin_m = Eigen::Vector3d::Zero();  // the food's left end, on its axis
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitX();  // unit, left end -> right end
  double requested_cut_m = 0.0;  // along the axis from axis_origin_m
  double start_height_m = 0.0;   // edge heights of the path
  double end_height_m = 0.0;
  // What happened.
  int substeps = 0;
  double min_dt_s = 0.0;  // shortest substep (s): below dt_s when a particle outran sound and knife
  double sim_time_s = 0.0;
  bool hit_time_limit = false;
  std::vector<mpm::Piece> pieces;
  std::vector<double> cut_positions_m;  // along the axis from axis_origin_m
  double peak_blade_force_n = 0.0;      // largest |force on blade| over the accumulation window
  double peak_blade_force_time_s = 0.0;
  double peak_substep_blade_force_n = 0.0;  // largest of a single substep (the sawtooth's tips)
  // Momentum balance over the run: the sum of the external impulses the solver reports (colliders,
  // gravity, tip force) against the food's momentum change, and their mismatch relative to the
  // collider impulse magnitude summed over substeps.
  Eigen::Vector3d blade_impulse_n_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d external_impulse_n_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d momentum_change_n_s = Eigen::Vector3d::Zero();
  double momentum_mismatch = 0.0;
  double worst_momentum_residual = 0.0;
  double j_min = 1.0;
  double j_max = 1.0;
  std::int64_t j_clamps = 0;
  std::int64_t speed_caps = 0;
  std::size_t broken_particles = 0;  // damage >= topology.broken_damage at the end
  double min_speed_factor = 1.0;     // slowest descent speed / descent_speed_m_s
  // The food's kinetic over its elastic energy, each integrated over the substeps the blade pushes
  // on it: mass scaling (sim/mpm/solver_config.h) stays quasi-static while this is small (< 0.1).
  double kinetic_to_elastic_energy = 0.0;
  // Particles integrated per substep over all particles, averaged over the substeps: below 1 where
  // activity (SceneSpec mpm.activity_radius) froze food far from the knife.
  double active_particle_fraction = 1.0;
  FinalParticles final_particles;
  // Wall time (ms).
  double compile_ms = 0.0;  // the food model, sampling included
  double setup_ms = 0.0;
  double p2g_ms = 0.0;
  double grid_ms = 0.0;
  double g2p_ms = 0.0;
  double topology_ms = 0.0;
  double total_ms = 0.0;  // compilation, substeps and topology
  double particle_steps_per_s = 0.0;  // particles x substeps / substep wall time
  double peak_memory_mb = 0.0;        // the process's peak resident memory (Linux; else 0)
};

// Resets the food as a server episode does, runs the cut and detects the pieces. `on_step` (may be
// empty) is called after every substep.
CutSummary RunCut(const CutModel& model, const CutStepCallback& on_step = {});

}  // namespace culinarycut::cc_cut
