// Every number the MLS-MPM cutting solver uses, with units and defaults (Drake-style plain
// config). The effects are switchable; a switched-off effect's code does not run.
#pragma once

#include <Eigen/Core>

namespace culinarycut::mpm {

struct Effects {
  bool plasticity = true;        // J2 radial return (materials with yield_stress_pa > 0)
  bool damage = true;            // fracture: damage in the blade band, and the cut record (cut_record.h)
  bool friction = true;          // Coulomb friction at knife, board and table; off: frictionless
  bool two_sided_blade = true;   // CPIC-style per-side grid near the blade: no leaking through it
  bool force_sensing = true;     // impulse -> force on blade, handle and board; momentum check
};

struct CuttingParameters {
  // Damage band half-width around the blade's edge: band = band0 (dx_ref / dx)^gamma (paper). With
  // the default gamma = -1 the band is a fixed number of cells (0.5 dx): narrow enough that the
  // cut leaves a gap of about one cell, wide enough that no particle slips past the edge intact.
  double band0_m = 0.002;
  double band_reference_dx_m = 0.004;
  double band_gamma = -1.0;
  // Approach-speed threshold v_th = (dx / dt) v_hat (paper); at the CFL step dx/dt is a multiple
  // of the wave speed, so v_th does not change with resolution.
  double v_hat = 2e-5;
  double c_hat_min = 0.01;          // damage grows only when the contact strength c-hat >= this
  // While gated on, D grows in proportion to how far the edge advances into the particle:
  // dD = damage_per_band * (approach speed * dt) / band, so a particle breaks once the edge has
  // pushed into it by band / damage_per_band, whatever the knife speed or time step.
  double damage_per_band = 2.0;
  // Quadratic speed resistance u <- u / (1 + k2 c-hat u dt), k2 = k2_0 (E / E_ref)(1 + sy / sy_ref).
  // The paper normalises c-hat by the grid speed dx / dt, so the slow-down per second grows with the
  // substep (about twice as much at CFL 0.4 as at 0.2). The resistance normalises it by the grid speed
  // at this CFL and real mass instead, c / resistance_cfl with c the touched food's wave speed: the
  // paper's value at CFL 0.2 in a one-food scene, no dt of its own at any CFL or mass scaling, and
  // none from a stiffer food elsewhere on the board.
  double resistance_cfl = 0.2;
  // The paper sums the edge nodes' approach speeds, which grow with the substep (1.7x from CFL 0.2 to
  // 0.8 on a cucumber cut). The resistance sums the edge's sweep instead, the engaged edge length times
  // the edge's speed into the food, and scales it by this gain: the approach speeds' sum over the sweep
  // per reference cell at CFL 0.2, 6.6, 4.8 and 6.6 on the cucumber, apple and banana of docs/accuracy.md.
  double resistance_approach_gain = 6.0;
  double k2_reference_per_s = 50.0;
  double k2_reference_youngs_pa = 1e6;
  double k2_reference_yield_pa = 1e5;
  // Tip force: a small acceleration pushing particles near the edge away from the blade plane,
  // to separate the sides and damp stick-slip (paper: "a small tip force"). 0 turns it off.
  double tip_acceleration_m_s2 = 2.0;
  double tip_band_cells = 1.0;      // how close to the edge (in dx) the tip force acts
};

// Activity (simulate only what the cut calls for, inside one food): food farther than radius_m
// from the blade that has come to rest is frozen, its stress a fixed load on the grid, until the
// blade comes near or its neighbours move it. Frozen food cannot sag, bend or rock: the price is
// measured in docs/accuracy.md. 0 = off: every particle is integrated every substep.
// The least activity radius in cells: a frozen particle must lie outside every active one's stencil
// (1.5 sqrt(3) dx), with a margin.
inline constexpr double kMinActivityRadiusCells = 5.0;

struct Activity {
  double radius_m = 0.0;             // from the blade's bounding box; 0 = off, else >= kMinActivityRadiusCells dx
  // A particle may freeze once its speed and |C_ij| dx stay below the sleep speed; food under a slow
  // knife (0.05 m/s) moves at a few mm/s throughout, so lower values freeze next to nothing.
  double sleep_speed_m_s = 3e-3;
  double wake_speed_m_s = 1e-2;      // a frozen particle wakes when a node it shares moves faster
  int check_every_substeps = 16;     // how often particles are checked (sooner for a fast knife)
  int quiet_checks = 4;              // consecutive quiet checks before a particle freezes
};

// The most mass scaling the solver and scenes accept: far past what keeps a cut quasi-static (the
// accuracy study's slow cut goes to x256), a bound on the stable step's growth (sqrt: 31.6x).
inline constexpr double kMaxMassScaling = 1000.0;

struct SolverConfig {
  double dx_m = 0.004;                  // grid spacing
  double cfl = 0.2;                     // dt <= cfl dx / c (paper: 0.2)
  double max_dt_s = 1e-3;               // upper bound even for very soft materials
  double j_min = 0.6;                   // J clamped to [j_min, j_max], isotropically
  double j_max = 1.6;
  double max_particle_speed_m_s = 20.0; // speed caps (counted in the diagnostics)
  double max_grid_speed_m_s = 20.0;
  double grid_damping_per_s = 0.0;      // mild velocity damping on the grid (0 = none)
  Eigen::Vector3d gravity_m_s2{0.0, 0.0, -9.81};
  // Mass scaling (the quasi-static device of explicit codes such as LS-DYNA): the food's inertia is
  // this many times its real mass, so the wave speed falls by sqrt(s) and the stable dt grows by it,
  // while its weight stays real (gravity acts on the scaled mass as g / s). Valid while the food's
  // kinetic energy stays small against its elastic energy; 1 = off.
  double mass_scaling = 1.0;            // in [1, kMaxMassScaling]
  // Empty cells around the particles' bounding box. One is all the stencils need (the box is refit
  // every substep); more changed nothing but rounding and cost 2-5 % of a cut (docs/benchmarks/grid_extent.md).
  int grid_margin_cells = 1;
  int threads = 1;                      // OpenMP threads; results do not depend on it
  Activity activity;
  Effects effects;
  CuttingParameters cutting;

  // What gravity does to the scaled mass: real weight, g / s of acceleration.
  Eigen::Vector3d weight_acceleration_m_s2() const { return gravity_m_s2 / mass_scaling; }
};

}  // namespace culinarycut::mpm
