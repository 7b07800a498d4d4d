#include "tools/cc_cut/solver_overrides.h"

namespace culinarycut::cc_cut {
namespace {

template <typename T>
void Set(const std::optional<T>& value, T* out) {
  if (value) *out = *value;
}

}  // namespace

void ApplySolverOverrides(const SolverOverrides& overrides, mpm::SolverConfig* config) {
  Set(overrides.threads, &config->threads);
  Set(overrides.max_dt_s, &config->max_dt_s);
  Set(overrides.j_min, &config->j_min);
  Set(overrides.j_max, &config->j_max);
  Set(overrides.max_particle_speed_m_s, &config->max_particle_speed_m_s);
  Set(overrides.max_grid_speed_m_s, &config->max_grid_speed_m_s);
  Set(overrides.grid_damping_per_s, &config->grid_damping_per_s);
  Set(overrides.gravity_m_s2, &config->gravity_m_s2);
  Set(overrides.grid_margin_cells, &config->grid_margin_cells);
  Set(overrides.activity_sleep_speed_m_s, &config->activity.sleep_speed_m_s);
  Set(overrides.activity_wake_speed_m_s, &config->activity.wake_speed_m_s);
  Set(overrides.activity_check_every_substeps, &config->activity.check_every_substeps);
  Set(overrides.activity_quiet_checks, &config->activity.quiet_checks);
  Set(overrides.two_sided_blade, &config->effects.two_sided_blade);
  const CuttingOverrides& cutting = overrides.cutting;
  mpm::CuttingParameters& out = config->cutting;
  Set(cutting.band0_m, &out.band0_m);
  Set(cutting.band_reference_dx_m, &out.band_reference_dx_m);
  Set(cutting.band_gamma, &out.band_gamma);
  Set(cutting.v_hat, &out.v_hat);
  Set(cutting.c_hat_min, &out.c_hat_min);
  Set(cutting.damage_per_band, &out.damage_per_band);
  Set(cutting.k2_reference_per_s, &out.k2_reference_per_s);
  Set(cutting.k2_reference_youngs_pa, &out.k2_reference_youngs_pa);
  Set(cutting.k2_reference_yield_pa, &out.k2_reference_yield_pa);
  Set(cutting.tip_acceleration_m_s2, &out.tip_acceleration_m_s2);
  Set(cutting.tip_band_cells, &out.tip_band_cells);
}

}  // namespace culinarycut::cc_cut
