// The MLS-MPM cutting solver (paper supplement "Details on MLS-MPM Simulation Method for
// Cutting"): one Substep is P2G -> grid update (gravity, colliders, two-sided blade) -> G2P
// (F update, J clamp, damage, tip force). The grid covers only the particles' neighbourhood.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/colliders.h"
#include "sim/mpm/cut_record.h"
#include "sim/mpm/materials.h"
#include "sim/mpm/particles.h"
#include "sim/mpm/solver_config.h"

namespace culinarycut::mpm {

struct SubstepContext;  // solver_internals.h
struct ContactState;
struct ParticleTotals;  // substep_totals.h
struct SubstepShared;   // solver_internals.h

// What one substep did and measured. Forces are those the food exerts on each collider (N,
// world frame), from the grid impulse F = -sum m (v_after - v_before) / dt.
struct SubstepDiagnostics {
  double dt_s = 0.0;
  Eigen::Vector3d force_on_blade_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_edge_n = Eigen::Vector3d::Zero();  // the edge's part of it (the rest: faces)
  Eigen::Vector3d force_on_handle_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_board_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_table_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d knife_velocity_m_s = Eigen::Vector3d::Zero();
  double c_hat = 0.0;                  // contact strength in [0, 1]
  // Speed resistance u / (1 + k2 c_hat u dt) at u = 1 (the knife's current speed): multiply the
  // knife speed by it, or apply the quadratic form at the caller's own u.
  double knife_speed_factor = 1.0;
  double j_min = 1.0;                  // smallest and largest J after the update
  double j_max = 1.0;
  std::int64_t j_clamps = 0;           // particles whose J was clamped this substep
  std::int64_t speed_caps = 0;         // particle and grid speeds capped this substep
  std::int64_t damaged_particles = 0;  // particles whose damage grew this substep
  double kinetic_energy_j = 0.0;
  double elastic_energy_j = 0.0;
  // The fastest particle's speed after the substep (m/s), the same bits as FastestParticleSpeed
  // of the particles now: it bounds the next substep's length (StableTimestep).
  double fastest_particle_m_s = 0.0;
  // Momentum balance: the food's momentum change against the sum of every impulse on it (N s):
  // gravity, damping, speed caps, tip force and the colliders; and their mismatch relative to the
  // larger of the collider impulse and the food's weight over the substep.
  Eigen::Vector3d momentum_change_n_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d external_impulse_n_s = Eigen::Vector3d::Zero();
  double momentum_residual = 0.0;
  Eigen::Vector3i grid_cells = Eigen::Vector3i::Zero();  // size of the grid box this substep
  std::int64_t active_particles = 0;   // particles integrated this substep (the rest frozen: Activity)
  // Wall time of the stages (ms): setup (grid box, blade labels, block sort), P2G, grid, G2P.
  double setup_ms = 0.0;
  double p2g_ms = 0.0;
  double grid_ms = 0.0;
  double g2p_ms = 0.0;
};

// The read-only inputs of a solver: its settings and the material table. A session's Model holds
// one; every solver made for an episode points at it rather than keeping a copy.
struct SolverModel {
  SolverConfig config;
  std::vector<Material> materials;
};

// The CFL-limited time step of a solver with this model: cfl dx / max over materials of
// sqrt((lambda + 2 mu) / rho), capped by max_dt_s (s).
// The CFL time step (s): dt <= cfl dx / c over the materials' wave speeds c, and <= max_dt_s.
double StableTimestep(const SolverModel& model);
// The same, and short enough that a collider moving at `collider_speed_m_s` crosses at most a CFL
// fraction of a cell per substep (a knife faster than sound would otherwise jump past particles).
double StableTimestep(const SolverModel& model, double collider_speed_m_s);
// The same, and short enough that the fastest particle (`particle_speed_m_s`, e.g. the last
// substep's SubstepDiagnostics::fastest_particle_m_s) moves at most a CFL fraction of a cell:
// food flung faster than its sound would otherwise skip cells and contacts in one substep.
double StableTimestep(const SolverModel& model, double collider_speed_m_s, double particle_speed_m_s);

// The fastest particle's speed max |v| (m/s); NaN velocities are ignored. A scan in one thread,
// giving the same bits as the substep's SubstepDiagnostics::fastest_particle_m_s.
template <typename Real>
double FastestParticleSpeed(const Particles<Real>& particles);

template <typename Real>
class Solver {
 public:
  // Throws std::invalid_argument for a bad config or material.
  explicit Solver(std::shared_ptr<const SolverModel> model);
  // A solver with a model of its own (tests, tools).
  Solver(const SolverConfig& config, std::vector<Material> materials);
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver& operator=(Solver&&) noexcept;

  Particles<Real>& particles() { return particles_; }
  const Particles<Real>& particles() const { return particles_; }
  const SolverConfig& config() const { return model_->config; }
  const std::vector<Material>& materials() const { return model_->materials; }

  // Colliders; absent ones are not simulated. The knife's motion is set by the caller each step.
  void SetKnife(const KnifeGeometry& geometry);
  void SetKnifeMotion(const RigidMotion& tcp_motion);
  void SetBoard(const Eigen::Vector3d& size_m, const RigidMotion& motion);
  void SetTable(double height_m);
  const KnifeSdf* knife() const { return knife_.get(); }

  // At most this many threads for the next substeps (the machine shared with other work); the
  // results are the same bits on any team, so this never changes what is simulated. 0: no limit.
  void SetThreadLimit(int threads) { thread_limit_ = threads; }
  // The team the next substep runs: the model's threads, within the limit.
  int team_size() const;

  // The CFL-limited time step of its model (s).
  double StableTimestep() const { return mpm::StableTimestep(*model_); }

  // Advances the food by dt_s with the colliders at their current motion.
  SubstepDiagnostics Substep(double dt_s);

  // Substeps taken so far. It decides when the particles are next reordered, so a snapshot keeps
  // it and a restore puts it back to replay bit for bit.
  std::uint64_t substeps_taken() const;
  void RestoreSubstepsTaken(std::uint64_t count);

  // Particles integrated by the last substep; the rest are frozen (SolverConfig::activity).
  std::size_t active_count() const { return active_count_; }

  // Puts the particles of food object `object` to sleep (frozen as activity freezes food: not
  // integrated, their mass and stress a fixed load on the grid, their velocity and affine field
  // dropped) or wakes them. Moving food that pushes a sleeping particle wakes it, as with activity;
  // with activity's radius on, the radius decides and this is overridden at its next check.
  void SetObjectAsleep(std::uint16_t object, bool asleep);

  // How many cuts the particles have recorded and whether one is under way (cut_record.h); a
  // snapshot keeps it so that a restored cut goes on recording into the same cut.
  const CutProgress& cut_progress() const { return cut_progress_; }
  void RestoreCutProgress(const CutProgress& progress);

 private:
  struct Grid;        // the bounded grid box (solver_internals.h)
  struct Workspace;   // per-substep scratch arrays, reused (solver_internals.h)
  struct FrozenLoad;  // what the frozen particles add to the grid (solver_internals.h)

  // The stages of Substep, in order; each file kernels/solver_<stage>.cc holds one. Substep runs them
  // all in one OpenMP parallel region: every thread of the team calls each stage, which shares its
  // work out inside (orphaned work-sharing; one fork and join per substep, few barriers).
  SubstepContext MakeContext(double dt_s) const;              // solver.cc
  // c-hat for the speed resistance, from the edge's sweep (m^2/s) at the touched food's wave speed
  // (CuttingParameters::resistance_cfl).
  double ResistanceContactStrength(double edge_sweep_m2_s, double wave_speed_m_s) const;  // solver.cc
  void PrepareWorkspace(int team);                            // solver_grid_box.cc, before the team
  void RunSubstepInTeam(const SubstepContext& context, SubstepShared* shared,
                        ContactState* contact);               // solver.cc, every thread
  void FindSplitCandidates(const SubstepContext& context);    // solver_blade_sides.cc, one thread
  void ScanParticles(const SubstepContext& context);          // solver_grid_box.cc, team
  void FitGridBox(const SubstepContext& context, Eigen::Vector3i* origin,
                  Eigen::Vector3i* dims) const;               // solver_grid_box.cc, every thread
  void SplitNodesNearBlade(const SubstepContext& context);    // solver_blade_sides.cc, a section
  CutCounts LabelBladeSides(const SubstepContext& context, std::size_t begin,
                       std::size_t end);                      // solver_blade_sides.cc, a chunk
  void SortParticlesIntoBlocks(const SubstepContext& context, const Eigen::Vector3i& origin,
                               const Eigen::Vector3i& dims,
                               SubstepShared* shared);        // solver_grid_box.cc, team
  double ComputeAffineMomentum(const SubstepContext& context, std::size_t begin,
                               std::size_t end, bool frozen_load = false);  // solver_stress.cc; J
  void ScatterToGrid(const SubstepContext& context);          // solver_p2g.cc, team
  void UpdateGrid(const SubstepContext& context, ContactState* contact);  // solver_grid_update.cc
  void GridToParticles(const SubstepContext& context,
                       const ContactState& contact);          // solver_g2p.cc, team
  // Activity (solver_activity.cc): before the team, freezes quiet particles far from the blade and
  // wakes those it nears or that were pushed, keeping the frozen ones last; rebuilds their load.
  void UpdateActivity(const SubstepContext& context);
  void BuildFrozenLoad(const SubstepContext& context);
  void AddFrozenLoad(const SubstepContext& context);          // one thread, after P2G
  void MarkPushedFrozenNodes();                               // one thread, after the grid update
  void WakePushedFrozenParticles();                           // after the team

  std::shared_ptr<const SolverModel> model_;  // shared, never copied
  Particles<Real> particles_;
  std::unique_ptr<KnifeSdf> knife_;
  std::optional<BoxSdf> board_;
  std::optional<HalfSpaceSdf> table_;
  std::unique_ptr<Grid> grid_;
  std::unique_ptr<Workspace> workspace_;
  std::unique_ptr<FrozenLoad> frozen_;
  std::size_t active_count_ = 0;  // particles [0, active_count_) are integrated
  CutProgress cut_progress_;
  int thread_limit_ = 0;  // SetThreadLimit; 0: the model's threads
};

// Throws std::invalid_argument naming the field at fault.
void ValidateSolverConfig(const SolverConfig& config);

}  // namespace culinarycut::mpm
