#include "sim/mpm/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

#include "sim/mpm/kernels/solver_internals.h"

namespace culinarycut::mpm {

void ValidateSolverConfig(const SolverConfig& config) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument("solver config: " + message);
  };
  require(config.dx_m > 0.0 && std::isfinite(config.dx_m), "dx_m must be > 0");
  require(config.cfl > 0.0 && config.cfl <= 1.0, "cfl must lie in (0, 1]");
  require(config.max_dt_s > 0.0, "max_dt_s must be > 0");
  require(config.j_min > 0.0 && config.j_min < 1.0 && config.j_max > 1.0,
          "need 0 < j_min < 1 < j_max");
  require(config.max_particle_speed_m_s > 0.0 && config.max_grid_speed_m_s > 0.0,
          "speed caps must be > 0");
  require(config.grid_damping_per_s >= 0.0, "grid_damping_per_s must be >= 0");
  require(config.gravity_m_s2.allFinite(), "gravity must be finite");
  require(config.mass_scaling >= 1.0 && config.mass_scaling <= kMaxMassScaling,
          "mass_scaling must lie in [1, " + std::to_string(static_cast<int>(kMaxMassScaling)) + "]");
  require(config.grid_margin_cells >= 1, "grid_margin_cells must be >= 1");
  require(config.threads >= 1, "threads must be >= 1");
  const Activity& activity = config.activity;
  // Frozen food must stay clear of the nodes split by the blade (2 dx beside it) with its whole
  // stencil (1.5 sqrt(3) dx), so the radius is at least 5 cells.
  require(activity.radius_m == 0.0 || (activity.radius_m >= kMinActivityRadiusCells * config.dx_m - 1e-12 &&
                                       std::isfinite(activity.radius_m)),
          "activity.radius_m must be 0 (off) or at least 5 dx");
  require(activity.sleep_speed_m_s >= 0.0 && activity.wake_speed_m_s > activity.sleep_speed_m_s,
          "need 0 <= activity.sleep_speed_m_s < activity.wake_speed_m_s");
  require(activity.check_every_substeps >= 1 && activity.quiet_checks >= 1 && activity.quiet_checks < 255,
          "activity.check_every_substeps must be >= 1 and activity.quiet_checks in [1, 254]");
  const CuttingParameters& cutting = config.cutting;
  require(cutting.band0_m > 0.0 && cutting.band_reference_dx_m > 0.0, "band0_m and "
          "band_reference_dx_m must be > 0");
  require(cutting.resistance_cfl > 0.0 && std::isfinite(cutting.resistance_cfl), "resistance_cfl must be > 0");
  require(cutting.resistance_approach_gain > 0.0 && std::isfinite(cutting.resistance_approach_gain),
          "resistance_approach_gain must be > 0");
  require(cutting.v_hat >= 0.0 && cutting.c_hat_min >= 0.0 && cutting.damage_per_band >= 0.0,
          "v_hat, c_hat_min and damage_per_band must be >= 0");
  require(cutting.k2_reference_per_s >= 0.0 && cutting.k2_reference_youngs_pa > 0.0 &&
              cutting.k2_reference_yield_pa > 0.0,
          "k2 parameters must be positive");
  require(cutting.tip_acceleration_m_s2 >= 0.0 && cutting.tip_band_cells >= 0.0,
          "tip force parameters must be >= 0");
}

template <typename Real>
Solver<Real>::Solver(std::shared_ptr<const SolverModel> model)
    : model_(std::move(model)),
      grid_(std::make_unique<Grid>()),
      workspace_(std::make_unique<Workspace>()),
      frozen_(std::make_unique<FrozenLoad>()) {
  if (!model_) throw std::invalid_argument("solver: no model");
  ValidateSolverConfig(config());
  if (materials().empty()) throw std::invalid_argument("solver: give at least one material");
  bool any_maxwell = false;
  for (const Material& material : materials()) {
    ValidateMaterial(material);
    any_maxwell = any_maxwell || material.maxwell_shear_modulus_pa() > 0.0;
  }
  if (any_maxwell && materials().size() > kMaxMaxwellMaterials) {
    throw std::invalid_argument("solver: at most " + std::to_string(kMaxMaxwellMaterials) +
                                " materials when any has a Maxwell branch (maxwell_modulus_ratio > 0)");
  }
}

template <typename Real>
Solver<Real>::Solver(const SolverConfig& config, std::vector<Material> materials)
    : Solver(std::make_shared<const SolverModel>(SolverModel{config, std::move(materials)})) {}

template <typename Real>
Solver<Real>::~Solver() = default;
template <typename Real>
Solver<Real>::Solver(Solver&&) noexcept = default;
template <typename Real>
Solver<Real>& Solver<Real>::operator=(Solver&&) noexcept = default;

template <typename Real>
void Solver<Real>::SetKnife(const KnifeGeometry& geometry) {
  knife_ = std::make_unique<KnifeSdf>(geometry, config().dx_m);
}

template <typename Real>
void Solver<Real>::SetKnifeMotion(const RigidMotion& tcp_motion) {
  if (!knife_) throw std::logic_error("SetKnifeMotion before SetKnife");
  knife_->SetMotion(tcp_motion);
}

template <typename Real>
void Solver<Real>::SetBoard(const Eigen::Vector3d& size_m, const RigidMotion& motion) {
  board_.emplace(size_m, motion);
}

template <typename Real>
void Solver<Real>::SetTable(double height_m) {
  table_.emplace(height_m);
}

template <typename Real>
std::uint64_t Solver<Real>::substeps_taken() const {
  return workspace_->substeps_since_reorder;
}

template <typename Real>
void Solver<Real>::RestoreSubstepsTaken(std::uint64_t count) {
  workspace_->substeps_since_reorder = count;
  frozen_->valid = false;  // the particles were restored with it: rebuild their load
}

template <typename Real>
int Solver<Real>::team_size() const {
  return thread_limit_ > 0 ? std::min(config().threads, thread_limit_) : config().threads;
}

template <typename Real>
void Solver<Real>::RestoreCutProgress(const CutProgress& progress) {
  if (progress.cuts_made > kMaxRecordedCuts || progress.current >= kMaxRecordedCuts ||
      progress.current > progress.cuts_made) {
    throw std::invalid_argument("RestoreCutProgress: cuts_made <= 16 and current <= min(cuts_made, 15)");
  }
  for (const BladeNormalMoment& moment : progress.blade_normals) {
    if (!(moment.duration_s >= 0.0 && std::isfinite(moment.duration_s) && moment.normal_outer_s.allFinite() &&
          moment.normal_outer_s.isApprox(moment.normal_outer_s.transpose()) &&
          std::abs(moment.normal_outer_s.trace() - moment.duration_s) <= 1e-9 * (1.0 + moment.duration_s))) {
      throw std::invalid_argument(
          "RestoreCutProgress: a blade normal moment must be symmetric and finite, its trace its duration (s) >= 0");
    }
  }
  cut_progress_ = progress;
}

double StableTimestep(const SolverModel& model) {
  double fastest_m_s = 0.0;
  for (const Material& material : model.materials) {
    fastest_m_s = std::max(fastest_m_s, material.dilatational_wave_speed_m_s());
  }
  fastest_m_s /= std::sqrt(model.config.mass_scaling);  // c = sqrt(M / (s rho))
  return std::min(model.config.max_dt_s, model.config.cfl * model.config.dx_m / fastest_m_s);
}

double StableTimestep(const SolverModel& model, double collider_speed_m_s) {
  const double dt_s = StableTimestep(model);
  if (!(collider_speed_m_s > 0.0)) return dt_s;
  return std::min(dt_s, model.config.cfl * model.config.dx_m / collider_speed_m_s);
}

double StableTimestep(const SolverModel& model, double collider_speed_m_s, double particle_speed_m_s) {
  return StableTimestep(model, std::max(collider_speed_m_s, particle_speed_m_s));
}

template <typename Real>
double FastestParticleSpeed(const Particles<Real>& particles) {
  double max_speed_sq = 0.0;  // (m/s)^2; std::max keeps it when a speed is NaN
  for (std::size_t q = 0; q < particles.size(); ++q) {
    max_speed_sq = std::max(max_speed_sq, SquaredSpeed(particles.velocity[0][q], particles.velocity[1][q],
                                                       particles.velocity[2][q]));
  }
  return std::sqrt(max_speed_sq);
}
template double FastestParticleSpeed(const Particles<float>&);
template double FastestParticleSpeed(const Particles<double>&);


template <typename Real>
double Solver<Real>::ResistanceContactStrength(double edge_sweep_m2_s, double wave_speed_m_s) const {
  const CuttingParameters& cutting = config().cutting;
  // What the paper's sum of approach speeds comes to at resistance_cfl, per reference cell of edge.
  const double approach_m_s = cutting.resistance_approach_gain * edge_sweep_m2_s / cutting.band_reference_dx_m;
  const double grid_speed_m_s = wave_speed_m_s / cutting.resistance_cfl;
  return std::min(1.0, approach_m_s / (kContactStrengthScale * grid_speed_m_s));
}

template <typename Real>
SubstepContext Solver<Real>::MakeContext(double dt_s) const {
  SubstepContext context;
  const double dx = config().dx_m;
  const CuttingParameters& cutting = config().cutting;
  context.dt_s = dt_s;
  context.dx_m = dx;
  context.knife_on = knife_ != nullptr;
  context.split_on = context.knife_on && config().effects.two_sided_blade;
  context.cut_index = static_cast<int>(cut_progress_.current);
  // Resolution-invariant cutting thresholds (paper): band and v_th rescale with dx and dt.
  context.band_m = cutting.band0_m * std::pow(cutting.band_reference_dx_m / dx, cutting.band_gamma);
  context.v_threshold_m_s = (dx / dt_s) * cutting.v_hat;
  context.blade_half_m = context.knife_on ? 0.5 * knife_->effective_thickness_m() : 0.0;
  // Particles get a side label a little further out than the split nodes, so every particle
  // touching a split node has one.
  context.split_half_width_m = context.blade_half_m + 2.0 * dx;
  context.half_length_m = context.knife_on ? 0.5 * knife_->geometry().blade_length_m : 0.0;
  context.blade_height_m = context.knife_on ? knife_->geometry().blade_height_m : 0.0;
  context.stencil_reach_m = 1.5 * std::sqrt(3.0) * dx + 1e-9;
  return context;
}

// Every thread of the team runs this; the stages share their work out inside and end with a
// barrier where the next stage needs all of it. Errors are kept for Substep to throw after the
// region (an exception may not leave it).
template <typename Real>
void Solver<Real>::RunSubstepInTeam(const SubstepContext& context, SubstepShared* shared,
                                    ContactState* contact) {
  using Clock = std::chrono::steady_clock;
  Clock::time_point stage_start = Clock::now();
  // Called right after a barrier: the master thread times the stage that just ended.
  auto end_stage = [&](int stage) {
#pragma omp master
    {
      const Clock::time_point now = Clock::now();
      shared->stage_ms[stage] = std::chrono::duration<double, std::milli>(now - stage_start).count();
      stage_start = now;
      shared->g2p_start = now;  // G2P ends with the region: Substep times it
    }
  };
  auto guarded = [shared](auto&& work) {
    try {
      work();
    } catch (...) {
#pragma omp critical(culinarycut_mpm_substep_error)
      {
        if (!shared->failed) shared->error = std::current_exception();
        shared->failed = true;
      }
    }
  };

  // Setup: one thread looks for split nodes near the blade while the others scan the particles
  // (bounds, side labels, momentum); then every thread fits the grid box from the bounds, and the
  // team sorts the particles into P2G blocks (and now and then stores them in that order).
#pragma omp single nowait
  guarded([&] { FindSplitCandidates(context); });
  ScanParticles(context);  // ends with a barrier
  Eigen::Vector3i origin, dims;
  bool box_ok = true;
  try {
    FitGridBox(context, &origin, &dims);  // the same on every thread, errors included
  } catch (...) {
    box_ok = false;
#pragma omp master
    shared->box_error = std::current_exception();
  }
  // Candidates' errors are read after the scan's barrier; box errors are every thread's own.
  if (!box_ok || shared->failed) return;
  SortParticlesIntoBlocks(context, origin, dims, shared);
  if (shared->failed) return;
  end_stage(0);

  // P2G: stress into each particle's affine momentum, then mass and momentum to the grid, and the
  // frozen particles' load.
  ScatterToGrid(context);  // ends with a barrier
#pragma omp single
  {
    AddFrozenLoad(context);
    double elastic_energy_j = frozen_->elastic_energy_j;
    for (const double energy : workspace_->elastic_energy_of_chunk) elastic_energy_j += energy;
    shared->elastic_energy_j = elastic_energy_j;
  }
  end_stage(1);

  // Grid update: velocities, gravity, damping, colliders and their impulses. Each thread gets
  // its own copy of the contact state; the master's goes to the diagnostics.
  ContactState own_contact;
  UpdateGrid(context, &own_contact);  // the node loop ends with a barrier
  end_stage(2);
  // One thread looks for frozen food pushed by its neighbours while the others start G2P (which
  // only reads the grid).
#pragma omp single nowait
  MarkPushedFrozenNodes();

  // G2P: velocity and affine field back, F update with J clamp, damage, tip force.
  GridToParticles(context, own_contact);  // no barrier: the region's end is one
#pragma omp master
  *contact = own_contact;
}

template <typename Real>
SubstepDiagnostics Solver<Real>::Substep(double dt_s) {
  if (!(dt_s > 0.0 && std::isfinite(dt_s))) {
    throw std::invalid_argument("Substep: dt_s must be a finite time > 0 s");
  }
  SubstepDiagnostics diagnostics;
  diagnostics.dt_s = dt_s;
  if (particles_.size() == 0) return diagnostics;
  // A new cut begins when the blade comes near the food after being clear of it.
  if (!cut_progress_.blade_in_food) {
    cut_progress_.current = std::min<std::uint32_t>(cut_progress_.cuts_made, kMaxRecordedCuts - 1);
  }
  const SubstepContext context = MakeContext(dt_s);
  // Particles built field by field (tests, tools) may lack the Maxwell branch's stress: start it at zero.
  for (auto& component : particles_.maxwell_stress) component.resize(particles_.size(), Real(0));
  UpdateActivity(context);
  if (active_count_ == 0) {  // all frozen: nothing moves, but the activity checks go on
    ++workspace_->substeps_since_reorder;
    return diagnostics;
  }

  // One parallel region for the whole substep (one fork and join).
  // No smaller team for few particles: the results are the same bits on any team, and the tests'
  // one-against-two-threads check (about 2000 particles) must run a real team of two.
  const int team = team_size();
  PrepareWorkspace(team);
  SubstepShared shared;
  ContactState contact;
#pragma omp parallel num_threads(team)
  RunSubstepInTeam(context, &shared, &contact);
  if (shared.failed || shared.box_error) {
    --workspace_->substeps_since_reorder;  // this substep did not happen
    std::rethrow_exception(shared.failed ? shared.error : shared.box_error);
  }
  shared.stage_ms[3] = std::chrono::duration<double, std::milli>(
                          std::chrono::steady_clock::now() - shared.g2p_start).count();
  WakePushedFrozenParticles();
  diagnostics.grid_cells = grid_->dims;
  diagnostics.active_particles = static_cast<std::int64_t>(active_count_);
  diagnostics.setup_ms = shared.stage_ms[0];
  diagnostics.p2g_ms = shared.stage_ms[1];
  diagnostics.grid_ms = shared.stage_ms[2];
  diagnostics.g2p_ms = shared.stage_ms[3];
  CutCounts cut_counts;
  for (const CutCounts& chunk : workspace_->cut_counts_of_chunk) {
    cut_counts.labelled += chunk.labelled;
    cut_counts.recorded += chunk.recorded;
  }
  cut_progress_.blade_in_food = cut_counts.labelled > 0;
  if (cut_counts.recorded > 0) {
    cut_progress_.cuts_made = std::max(cut_progress_.cuts_made, cut_progress_.current + 1);
    // The edge passed food this substep: the blade's pose counts towards this cut's orientation.
    if (context.knife_on) {
      cut_progress_.blade_normals[cut_progress_.current].Add(knife_->motion().pose.linear().col(1), dt_s);
    }
  }
  const GridTotals& grid_totals = contact.totals;
  ParticleTotals particle_totals = SumChunks(workspace_->particle_chunks);
  particle_totals.elastic_energy = shared.elastic_energy_j;
  Eigen::Vector3d momentum_before = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& chunk : workspace_->momentum_of_chunk) momentum_before += chunk;

  // Diagnostics: the sums of the stages, the forces on the colliders, the momentum check.
  diagnostics.j_min = particle_totals.j_min;
  diagnostics.j_max = particle_totals.j_max;
  diagnostics.j_clamps = particle_totals.j_clamps;
  diagnostics.speed_caps = particle_totals.speed_caps + grid_totals.speed_caps;
  diagnostics.damaged_particles = particle_totals.damaged;
  diagnostics.kinetic_energy_j = particle_totals.kinetic_energy;
  diagnostics.elastic_energy_j = particle_totals.elastic_energy;
  diagnostics.fastest_particle_m_s = std::sqrt(particle_totals.max_speed_sq);
  diagnostics.c_hat = contact.c_hat;
  diagnostics.knife_velocity_m_s =
      context.knife_on ? knife_->motion().linear_velocity_m_s : Eigen::Vector3d::Zero();
  if (config().effects.force_sensing) {
    // The food pushes each collider with minus the impulse the collider gave it (paper eq. force).
    diagnostics.force_on_blade_n = -grid_totals.blade_impulse / dt_s;
    diagnostics.force_on_edge_n = -grid_totals.edge_impulse / dt_s;
    diagnostics.force_on_handle_n = -grid_totals.handle_impulse / dt_s;
    diagnostics.force_on_board_n = -grid_totals.board_impulse / dt_s;
    diagnostics.force_on_table_n = -grid_totals.table_impulse / dt_s;
    const Eigen::Vector3d collider_impulse = grid_totals.blade_impulse + grid_totals.handle_impulse +
                                             grid_totals.board_impulse + grid_totals.table_impulse;
    diagnostics.momentum_change_n_s = particle_totals.momentum - momentum_before;
    diagnostics.external_impulse_n_s =
        collider_impulse + grid_totals.other_impulse + particle_totals.particle_impulse;
    // Relative to the larger of the contact impulse and the food's weight over the substep.
    const double scale = std::max(collider_impulse.norm(),
                                  grid_totals.mass * config().weight_acceleration_m_s2().norm() * dt_s);
    diagnostics.momentum_residual =
        scale > 0.0
            ? (diagnostics.momentum_change_n_s - diagnostics.external_impulse_n_s).norm() / scale
            : 0.0;
  }
  // Quadratic speed resistance (paper): u <- u / (1 + k2 c-hat u dt) with u = 1 the current speed;
  // k2 and the wave speed are the touched foods' (SpeedResistance), weighted by the edge length each
  // engages, and c-hat is taken from the edge's sweep at a grid speed free of the substep
  // (CuttingParameters::resistance_cfl, resistance_approach_gain).
  if (context.knife_on && grid_totals.edge_sweep_m2_s > 0.0) {
    const ContactMaterials& foods = workspace_->contact_materials;
    const ContactMaterial& only = foods.At(Eigen::Vector3d::Zero());  // every food's, when uniform
    const double sweep = grid_totals.edge_sweep_m2_s;
    const double k2 = foods.uniform() ? only.k2_per_s : grid_totals.resistance_sum / sweep;
    const double wave_speed_m_s = foods.uniform() ? only.wave_speed_m_s : grid_totals.wave_speed_sum / sweep;
    const double c_hat = ResistanceContactStrength(sweep, wave_speed_m_s);
    diagnostics.knife_speed_factor = 1.0 / (1.0 + k2 * c_hat * dt_s);
  }
  return diagnostics;
}

template class Solver<float>;
template class Solver<double>;

}  // namespace culinarycut::mpm
