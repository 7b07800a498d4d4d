// A knife cut for the tests: the blade stands across the world x axis at x = cut_x_m and
// descends through the food on the board, then lifts out; records what the tests check.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/topology.h"

namespace culinarycut::mpm::testing {

struct CutScenario {
  double cut_x_m = 0.5;            // blade plane
  double start_height_m = 0.08;    // TCP (edge) height at the start
  double end_height_m = 0.019;     // lowest edge height (board top is 0.02 m)
  double speed_m_s = 0.5;          // descent speed
  double settle_s = 0.02;          // after lifting out
  double lift_speed_m_s = 1.0;
  double lift_to_m = 0.08;         // edge height the knife lifts back to
  double saw_amplitude_m = 0.0;    // back and forth along the blade (world y) while descending
  double saw_frequency_hz = 0.0;
  double yaw_rad = 0.0;            // the blade turned about the vertical (0: across world x)
};

struct CutResult {
  int steps = 0;
  std::int64_t side_violations = 0;   // labelled particles found on the other side of the blade
  double worst_momentum_residual = 0.0;  // while the blade pushes with > 5 % of its peak force
  double peak_blade_force_n = 0.0;
  double peak_force_before_contact_n = 0.0;
  bool finite = true;
  double j_min = 1.0, j_max = 1.0;
  double max_kinetic_energy_j = 0.0;
  double max_c_hat = 0.0;
  double max_elastic_energy_j = 0.0;
  std::int64_t j_clamps = 0;
  std::int64_t speed_caps = 0;           // particle and node speeds capped, summed over substeps
  double max_knife_speed_m_s = 0.0;
  double fastest_particle_m_s = 0.0;     // the fastest any particle moved after a substep
  std::int64_t broken_particles = 0;     // damage >= 0.9 at the end
  std::vector<double> blade_force_z_n;   // per substep
  std::vector<double> edge_force_z_n;    // per substep: the edge's part of the blade force
  std::vector<double> knife_height_m;    // edge height per substep
  std::vector<double> dt_s;              // per substep
  std::vector<std::int64_t> active_particles;  // per substep: those integrated (activity)
  std::vector<double> residuals;
};

// The TCP frame for a blade across x: blade normal (TCP y) along +x, edge down (TCP z = -z).
inline Eigen::Matrix3d BladeAcrossX() {
  Eigen::Matrix3d rotation;
  rotation.col(0) = Eigen::Vector3d(0, 1, 0);
  rotation.col(1) = Eigen::Vector3d(1, 0, 0);
  rotation.col(2) = Eigen::Vector3d(0, 0, -1);
  return rotation;
}

template <typename Real>
void AddBoardAndTable(Solver<Real>* solver) {
  RigidMotion board;
  board.pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.01);
  solver->SetBoard(Eigen::Vector3d(0.4, 0.3, 0.02), board);
  solver->SetTable(0.0);
}

// A soft block on the board, 6 x 3 x 3 cm around (0.5, 0, 0.035) m, 8 particles per 4 mm cell.
inline std::unique_ptr<Solver<float>> SoftBlockOnBoard(const SolverConfig& config) {
  auto solver = std::make_unique<Solver<float>>(config, std::vector<Material>{SoftMaterial(5e4, 0.3)});
  AddBlock<float>({0.47, -0.015, 0.02}, {0.53, 0.015, 0.05}, config.dx_m, 2, 1000.0,
                  &solver->particles());
  AddBoardAndTable(solver.get());
  return solver;
}

// The mean of `force_n` (per substep) over the substeps in which the descending edge was between
// `low_m` and `high_m`: the force averaged over that stretch of the cut (N).
inline double MeanForceWhileDescending(const CutResult& cut, const std::vector<double>& force_n,
                                       double low_m, double high_m) {
  double impulse_n_s = 0.0, time_s = 0.0;
  for (std::size_t s = 0; s < force_n.size(); ++s) {
    const double h = cut.knife_height_m[s];
    if (!(h >= low_m && h <= high_m)) continue;  // NaN while lifting
    impulse_n_s += force_n[s] * cut.dt_s[s];
    time_s += cut.dt_s[s];
  }
  return time_s > 0.0 ? impulse_n_s / time_s : 0.0;
}

// A 4 x 2 x 2 cm block of `material` on the board, centred at x = 0.5 m, 8 particles per cell.
inline Solver<float> SmallBlockOnBoard(const Material& material, double dx_m = 0.004) {
  SolverConfig config;
  config.dx_m = dx_m;
  Solver<float> solver(config, {material});
  AddBlock<float>({0.48, -0.01, 0.02}, {0.52, 0.01, 0.04}, config.dx_m, 2, 1000.0, &solver.particles());
  AddBoardAndTable(&solver);
  return solver;
}

template <typename Real>
CutResult RunCut(const CutScenario& scenario, Solver<Real>* solver) {
  CutResult result;
  solver->SetKnife(KnifeGeometry{});
  // Short enough for sound, for the knife's fastest motion (descent, lift or saw) and for the
  // fastest particle of the substep before, as cc-cut chooses it.
  const double fastest_knife_m_s =
      std::max({scenario.speed_m_s, scenario.lift_speed_m_s,
                2.0 * M_PI * scenario.saw_frequency_hz * scenario.saw_amplitude_m});
  const SolverModel model{solver->config(), solver->materials()};
  double fastest_particle_m_s = FastestParticleSpeed(solver->particles());
  double height = scenario.start_height_m;
  double time_s = 0.0;
  bool lifting = false;
  double settle_left = scenario.settle_s;
  std::vector<double> forces;
  std::vector<double> residuals;
  while (true) {
    const double dt = StableTimestep(model, fastest_knife_m_s, fastest_particle_m_s);
    RigidMotion motion;
    motion.pose.linear() =
        Eigen::AngleAxisd(scenario.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        BladeAcrossX();
    const double phase = 2.0 * M_PI * scenario.saw_frequency_hz * time_s;
    const double saw_y = lifting ? 0.0 : scenario.saw_amplitude_m * std::sin(phase);
    const double saw_vy = lifting ? 0.0
                                  : scenario.saw_amplitude_m * 2.0 * M_PI *
                                        scenario.saw_frequency_hz * std::cos(phase);
    motion.pose.translation() = Eigen::Vector3d(scenario.cut_x_m, saw_y, height);
    const double vz = lifting ? scenario.lift_speed_m_s : -scenario.speed_m_s;
    motion.linear_velocity_m_s =
        Eigen::Vector3d(0, saw_vy, height >= scenario.lift_to_m && lifting ? 0.0 : vz);
    result.max_knife_speed_m_s = std::max(result.max_knife_speed_m_s, motion.linear_velocity_m_s.norm());
    solver->SetKnifeMotion(motion);
    const SubstepDiagnostics d = solver->Substep(dt);
    fastest_particle_m_s = d.fastest_particle_m_s;
    result.fastest_particle_m_s = std::max(result.fastest_particle_m_s, fastest_particle_m_s);
    ++result.steps;
    const double force = d.force_on_blade_n.norm();
    forces.push_back(force);
    residuals.push_back(d.momentum_residual);
    result.blade_force_z_n.push_back(d.force_on_blade_n.z());
    result.edge_force_z_n.push_back(d.force_on_edge_n.z());
    result.knife_height_m.push_back(lifting ? std::numeric_limits<double>::quiet_NaN() : height);
    result.dt_s.push_back(dt);
    result.active_particles.push_back(d.active_particles);
    result.j_min = std::min(result.j_min, d.j_min);
    result.j_max = std::max(result.j_max, d.j_max);
    result.max_kinetic_energy_j = std::max(result.max_kinetic_energy_j, d.kinetic_energy_j);
    result.max_c_hat = std::max(result.max_c_hat, d.c_hat);
    result.max_elastic_energy_j = std::max(result.max_elastic_energy_j, d.elastic_energy_j);
    result.j_clamps += d.j_clamps;
    result.speed_caps += d.speed_caps;
    result.finite = result.finite && std::isfinite(d.kinetic_energy_j) && std::isfinite(force) &&
                    std::isfinite(d.elastic_energy_j);

    // Labelled particles must never come out of the blade's far face while the blade stands
    // between the sides (a particle caught inside the blade's thickness has not crossed it).
    const KnifeSdf& knife = *solver->knife();
    const auto& p = solver->particles();
    for (std::size_t q = 0; q < p.size(); ++q) {
      if (p.blade_side[q] == 0) continue;
      const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
      if (!knife.WithinBladeLength(x) || knife.HeightAboveEdge(x) < 0.0) continue;
      const double own_side_m = p.blade_side[q] > 0 ? knife.SideOfBlade(x) : -knife.SideOfBlade(x);
      if (own_side_m < -0.5 * knife.effective_thickness_m()) ++result.side_violations;
    }
    time_s += dt;
    if (!lifting) {
      height -= scenario.speed_m_s * dt;
      if (height <= scenario.end_height_m) lifting = true;
    } else if (height < scenario.lift_to_m) {
      height += scenario.lift_speed_m_s * dt;
    } else {
      settle_left -= dt;
      if (settle_left <= 0.0) break;
    }
  }
  result.peak_blade_force_n = *std::max_element(forces.begin(), forces.end());
  for (const auto damage : solver->particles().damage) result.broken_particles += damage >= 0.9;
  for (int axis = 0; axis < 3; ++axis) {
    for (const auto x : solver->particles().position[axis]) result.finite = result.finite && std::isfinite(x);
  }
  for (std::size_t s = 0; s < forces.size(); ++s) {
    if (forces[s] > 0.05 * result.peak_blade_force_n) {
      result.worst_momentum_residual = std::max(result.worst_momentum_residual, residuals[s]);
    }
  }
  return result;
}

}  // namespace culinarycut::mpm::testing
