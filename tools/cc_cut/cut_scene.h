// A knife-cut scene as plain config: one food on the board, a material preset with overrides, the
// solver's settings and the knife's path. CutSceneFromJson reads it from a JSON file's text;
// RunCutScene simulates it substep by substep, reporting each substep's diagnostics, and returns
// what came out (pieces, cut positions, forces, momentum balance, timings). Schema and units:
// tools/cc_cut/README.md.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/mpm/materials.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/solver_config.h"
#include "sim/mpm/topology.h"

namespace culinarycut::mpm {

struct CutSceneFood {
  std::string name = "cucumber";  // a FoodShapeNames() entry
  double scale = 1.0;             // multiplies the food's typical size
  // Centre of the food's bounding box in the world (m). Without z, the food rests on the board.
  Eigen::Vector2d position_xy_m{0.5, 0.0};
  std::optional<double> position_z_m;
  double yaw_deg = 0.0;  // rotation about world z; 0: long axis along world x
};

// A material preset (MaterialPresetNames(); empty: the food's own preset) with overrides.
struct CutSceneMaterial {
  std::string preset;
  std::optional<double> youngs_modulus_pa;
  std::optional<double> poisson_ratio;
  std::optional<double> density_kg_m3;
  std::optional<double> yield_stress_pa;
  std::optional<double> friction_coefficient;
  std::optional<double> viscoplastic_relaxation_time_s;
};

// The knife's path: the blade stands across the food's long axis (blade normal along it), edge
// down, descends from above the food's top to below its bottom, then lifts back and waits.
struct CutSceneKnife {
  // Where the blade crosses the long axis: a fraction of the food's length from its -x end, or a
  // coordinate along the axis from the food's centre (m). At most one is given; default 0.5.
  std::optional<double> cut_fraction;
  std::optional<double> cut_local_x_m;
  double start_above_top_m = 0.006;   // edge height above the food's top at the start
  double end_below_bottom_m = 0.001;  // lowest edge position below the food's bottom
  double descent_speed_m_s = 0.5;
  double saw_amplitude_m = 0.0;  // back and forth along the blade while descending
  double saw_frequency_hz = 0.0;
  double lift_speed_m_s = 1.0;  // back up to the start height after the descent
  double settle_s = 0.02;       // simulated after the knife is back up
  // Slow the descent by the solver's knife_speed_factor (quadratic speed resistance), never below
  // min_speed_fraction of descent_speed_m_s.
  bool apply_speed_resistance = false;
  double min_speed_fraction = 0.1;
  double max_time_s = 10.0;  // the run stops here whatever the knife's phase
};

struct CutScene {
  std::string description;  // free text, not used
  CutSceneFood food;
  CutSceneMaterial material;
  SolverConfig solver;
  int particles_per_cell = 8;
  CutSceneKnife knife;
  std::uint64_t seed = 0;  // particle sampling jitter
};

// Parses a scene; absent fields keep their defaults. Throws std::invalid_argument whose message
// names the field ("knife.descent_speed_m_s: must be > 0, got -1"): unknown key, wrong type, out of
// range, or a bad preset / food name.
CutScene CutSceneFromJson(const std::string& json_text);
// Every field, defaults included, as JSON (CutSceneFromJson reads it back to an equal scene;
// an unset cut position is written as cut_fraction 0.5).
std::string CutSceneToJson(const CutScene& scene);
// The material the scene uses: preset plus overrides. Throws like CutSceneFromJson.
Material ResolveMaterial(const CutScene& scene);

// One substep as the callback sees it.
struct CutStepRecord {
  int step = 0;                 // 0, 1, ...
  double time_s = 0.0;          // simulated time at the end of this substep
  double knife_height_m = 0.0;  // edge (TCP) height during this substep
  SubstepDiagnostics diagnostics;
};
using CutStepCallback = std::function<void(const CutStepRecord&)>;

struct CutSceneSummary {
  // What the scene resolved to.
  Material material;
  double dt_s = 0.0;
  std::size_t particles = 0;
  double food_length_m = 0.0;                               // along the long axis
  Eigen::Vector3d axis_origin_m = Eigen::Vector3d::Zero();  // the food's -x end, on its axis
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitX();
  double requested_cut_m = 0.0;  // along the axis from axis_origin_m
  double start_height_m = 0.0;   // edge heights of the path
  double end_height_m = 0.0;
  TopologyOptions topology;
  Eigen::Vector3d board_size_m{0.40, 0.30, 0.02};
  Eigen::Vector3d board_centre_m{0.5, 0.0, 0.01};
  double table_height_m = 0.0;
  // What happened.
  int substeps = 0;
  double sim_time_s = 0.0;
  bool hit_time_limit = false;
  std::vector<Piece> pieces;
  std::vector<double> cut_positions_m;  // along the axis from axis_origin_m
  double peak_blade_force_n = 0.0;      // largest |force on blade|
  double peak_blade_force_time_s = 0.0;
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
  // Wall time (ms).
  double sampling_ms = 0.0;
  double setup_ms = 0.0;
  double p2g_ms = 0.0;
  double grid_ms = 0.0;
  double g2p_ms = 0.0;
  double topology_ms = 0.0;
  double total_ms = 0.0;
  double particle_steps_per_s = 0.0;  // particles x substeps / substep wall time
};

// Builds the solver and the scene, runs the cut and detects the pieces. `on_step` (may be empty)
// is called after every substep. Throws std::invalid_argument for a bad scene.
CutSceneSummary RunCutScene(const CutScene& scene, const CutStepCallback& on_step = {});

}  // namespace culinarycut::mpm
