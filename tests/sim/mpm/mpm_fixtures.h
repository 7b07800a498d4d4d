// Small helpers for the MPM tests: lattice-sampled blocks and whole-body measures.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "sim/mpm/materials.h"
#include "sim/mpm/particles.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm::testing {

// Fills the box [low, high] with a regular lattice of `per_axis`^3 particles per dx^3 cell.
template <typename Real>
void AddBlock(const Eigen::Vector3d& low, const Eigen::Vector3d& high, double dx, int per_axis,
              double density_kg_m3, Particles<Real>* particles, std::uint16_t object = 0,
              std::uint16_t material = 0) {
  const double spacing = dx / per_axis;
  const Eigen::Vector3i counts = ((high - low) / spacing).array().round().cast<int>();
  const double volume = spacing * spacing * spacing;
  for (int i = 0; i < counts.x(); ++i) {
    for (int j = 0; j < counts.y(); ++j) {
      for (int k = 0; k < counts.z(); ++k) {
        const Eigen::Vector3d x = low + spacing * (Eigen::Vector3d(i, j, k).array() + 0.5).matrix();
        particles->Add({Real(x.x()), Real(x.y()), Real(x.z())}, Real(density_kg_m3 * volume),
                       Real(volume), material, object);
      }
    }
  }
}

template <typename Real>
Eigen::Vector3d Momentum(const Particles<Real>& p) {
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (std::size_t q = 0; q < p.size(); ++q) {
    for (int a = 0; a < 3; ++a) total[a] += double(p.mass[q]) * p.velocity[a][q];
  }
  return total;
}

template <typename Real>
Eigen::Vector3d CentreOfMass(const Particles<Real>& p) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double mass = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    for (int a = 0; a < 3; ++a) sum[a] += double(p.mass[q]) * p.position[a][q];
    mass += p.mass[q];
  }
  return sum / mass;
}

// APIC angular momentum about the origin: x × m v plus each particle's spread, m dx^2 / 4 times
// the axial vector of its affine field C (quadratic B-splines: D = dx^2 / 4 I).
template <typename Real>
Eigen::Vector3d AngularMomentum(const Particles<Real>& p, double dx) {
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (std::size_t q = 0; q < p.size(); ++q) {
    const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
    const Eigen::Vector3d v(p.velocity[0][q], p.velocity[1][q], p.velocity[2][q]);
    const double m = p.mass[q];
    auto c = [&](int i, int j) { return double(p.C[3 * i + j][q]); };
    const Eigen::Vector3d axial(c(2, 1) - c(1, 2), c(0, 2) - c(2, 0), c(1, 0) - c(0, 1));
    total += m * x.cross(v) + m * dx * dx / 4.0 * axial;
  }
  return total;
}

// A soft elastic test material (fast to simulate: low wave speed).
inline Material SoftMaterial(double youngs_pa = 1e5, double poisson = 0.3) {
  Material material = MaterialPreset("generic");
  material.name = "soft";
  material.youngs_modulus_pa = youngs_pa;
  material.poisson_ratio = poisson;
  material.density_kg_m3 = 1000.0;
  material.yield_stress_pa = 0.0;
  return material;
}

// Steps `solver` at its stable dt until the mean `axis` velocity of the particles with x below
// `end_x_m` (one end of a bar or beam along x) first turns from positive to non-positive; returns
// that time (s), linearly interpolated within the substep, or 0 if it does not within `max_steps`.
inline double FirstEndVelocityReversal(Solver<double>* solver, int axis, double end_x_m, int max_steps) {
  const Particles<double>& p = solver->particles();
  auto end_velocity = [&] {
    double sum = 0.0;
    int count = 0;
    for (std::size_t q = 0; q < p.size(); ++q) {
      if (p.position[0][q] < end_x_m) {
        sum += p.velocity[axis][q];
        ++count;
      }
    }
    return sum / count;
  };
  const double dt = solver->StableTimestep();
  double previous = end_velocity();
  for (int s = 1; s < max_steps; ++s) {
    solver->Substep(dt);
    const double current = end_velocity();
    if (previous > 0.0 && current <= 0.0) return dt * (s - 1 + previous / (previous - current));
    previous = current;
  }
  return 0.0;
}

}  // namespace culinarycut::mpm::testing
