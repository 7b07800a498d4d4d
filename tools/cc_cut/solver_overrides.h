// What cc-cut may change of the solver the server would build: the numbers SceneSpec does not carry
// (the J clamp, speed caps, damping, gravity, the blade's two sides, the cutting parameters,
// threads). Each unset value keeps the server's.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "sim/mpm/solver_config.h"

namespace culinarycut::cc_cut {

// The cutting parameters of mpm::CuttingParameters, each optional.
struct CuttingOverrides {
  std::optional<double> band0_m;
  std::optional<double> band_reference_dx_m;
  std::optional<double> band_gamma;
  std::optional<double> v_hat;
  std::optional<double> c_hat_min;
  std::optional<double> damage_per_band;
  std::optional<double> k2_reference_per_s;
  std::optional<double> k2_reference_youngs_pa;
  std::optional<double> k2_reference_yield_pa;
  std::optional<double> tip_acceleration_m_s2;
  std::optional<double> tip_band_cells;
};

struct SolverOverrides {
  std::optional<int> threads;
  std::optional<double> max_dt_s;
  std::optional<double> j_min;
  std::optional<double> j_max;
  std::optional<double> max_particle_speed_m_s;
  std::optional<double> max_grid_speed_m_s;
  std::optional<double> grid_damping_per_s;
  std::optional<Eigen::Vector3d> gravity_m_s2;
  std::optional<int> grid_margin_cells;
  // Activity's thresholds (sim/mpm/solver_config.h); its radius is the scene's mpm.activity_radius.
  std::optional<double> activity_sleep_speed_m_s;
  std::optional<double> activity_wake_speed_m_s;
  std::optional<int> activity_check_every_substeps;
  std::optional<int> activity_quiet_checks;
  std::optional<bool> two_sided_blade;
  CuttingOverrides cutting;
};

// Sets every value `overrides` holds. The caller validates the result (mpm::ValidateSolverConfig).
void ApplySolverOverrides(const SolverOverrides& overrides, mpm::SolverConfig* config);

}  // namespace culinarycut::cc_cut
