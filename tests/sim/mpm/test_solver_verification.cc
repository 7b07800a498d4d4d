// MLS-MPM against problems with known answers (closed-form solutions: bar waves, a column under gravity, rest without creep).
#include <cmath>

#include <catch2/catch.hpp>

#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

using testing::AddBlock;
using testing::SoftMaterial;

TEST_CASE("free fall follows x0 + v0 t + g t^2 / 2", "[mpm][verification]") {
  SolverConfig config;
  config.dx_m = 0.01;
  Solver<double> solver(config, {SoftMaterial()});
  AddBlock<double>({0.4, -0.01, 1.0}, {0.42, 0.01, 1.02}, config.dx_m, 2, 1000.0,
                   &solver.particles());
  const Eigen::Vector3d v0(0.3, -0.2, 1.5);
  auto& p = solver.particles();
  for (std::size_t q = 0; q < p.size(); ++q) {
    for (int a = 0; a < 3; ++a) p.velocity[a][q] = v0[a];
  }
  const Eigen::Vector3d x0 = testing::CentreOfMass(p);
  const double dt = 2e-6;
  const int steps = 10000;
  for (int s = 0; s < steps; ++s) solver.Substep(dt);
  const double t = dt * steps;
  const Eigen::Vector3d expected = x0 + v0 * t + 0.5 * config.gravity_m_s2 * t * t;
  const Eigen::Vector3d actual = testing::CentreOfMass(p);
  // Symplectic Euler lags by g t dt / 2 = 2e-7 m here: within 1e-6 of the position.
  CHECK((actual - expected).norm() / expected.norm() < 1e-6);
  // ... and within dt / t = 1e-4 of the displacement itself.
  CHECK((actual - expected).norm() / (expected - x0).norm() < 1.1e-4);
  // Every particle moved rigidly: no spurious deformation.
  for (std::size_t q = 0; q < p.size(); ++q) CHECK(std::abs(p.F[0][q] - 1.0) < 1e-9);
}

TEST_CASE("a spinning free body keeps its linear and angular momentum", "[mpm][verification]") {
  SolverConfig config;
  config.dx_m = 0.01;
  config.gravity_m_s2.setZero();
  Solver<double> solver(config, {SoftMaterial(2e5)});
  AddBlock<double>({-0.04, -0.03, -0.02}, {0.04, 0.03, 0.02}, config.dx_m, 2, 1000.0,
                   &solver.particles());
  auto& p = solver.particles();
  const Eigen::Vector3d omega(1.0, -2.0, 3.0);  // rad/s
  const Eigen::Vector3d drift(0.2, 0.1, -0.05);  // m/s
  for (std::size_t q = 0; q < p.size(); ++q) {
    const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
    const Eigen::Vector3d v = drift + omega.cross(x);
    for (int a = 0; a < 3; ++a) p.velocity[a][q] = v[a];
    // The affine field of a rigid rotation: C = [omega]_x.
    const Eigen::Matrix3d skew = (Eigen::Matrix3d() << 0, -omega.z(), omega.y(), omega.z(), 0,
                                  -omega.x(), -omega.y(), omega.x(), 0).finished();
    for (int k = 0; k < 9; ++k) p.C[k][q] = skew(k / 3, k % 3);
  }
  const Eigen::Vector3d momentum0 = testing::Momentum(p);
  const Eigen::Vector3d angular0 = testing::AngularMomentum(p, config.dx_m);
  const double dt = solver.StableTimestep();
  for (int s = 0; s < 1000; ++s) solver.Substep(dt);
  CHECK((testing::Momentum(p) - momentum0).norm() / momentum0.norm() < 1e-5);
  CHECK((testing::AngularMomentum(p, config.dx_m) - angular0).norm() / angular0.norm() < 1e-5);
}

TEST_CASE("a free-free elastic bar rings at the bar wave speed", "[mpm][verification]") {
  // nu = 0: bar speed sqrt(E / rho) equals the dilatational speed; first mode u ~ cos(pi x / L)
  // oscillates with period 2 L / c, so the end velocity first reverses at t = L / (2 c).
  SolverConfig config;
  config.dx_m = 0.005;
  config.gravity_m_s2.setZero();
  const Material bar = SoftMaterial(1e5, 0.0);
  Solver<double> solver(config, {bar});
  const double length_m = 0.4;
  AddBlock<double>({0.0, 0.0, 0.0}, {length_m, 0.01, 0.01}, config.dx_m, 2, 1000.0,
                   &solver.particles());
  auto& p = solver.particles();
  const double v0 = 0.01;  // m/s: small strain
  for (std::size_t q = 0; q < p.size(); ++q) {
    p.velocity[0][q] = v0 * std::cos(M_PI * p.position[0][q] / length_m);
  }
  const double c_expected = std::sqrt(bar.youngs_modulus_pa / bar.density_kg_m3);
  const double dt = solver.StableTimestep();
  // End-region mean velocity along the bar.
  auto end_velocity = [&] {
    double sum = 0.0;
    int count = 0;
    for (std::size_t q = 0; q < p.size(); ++q) {
      if (p.position[0][q] < 0.02) {
        sum += p.velocity[0][q];
        ++count;
      }
    }
    return sum / count;
  };
  double previous = end_velocity();
  double crossing_s = 0.0;
  for (int s = 1; s < 2000 && crossing_s == 0.0; ++s) {
    solver.Substep(dt);
    const double current = end_velocity();
    if (previous > 0.0 && current <= 0.0) {
      crossing_s = dt * (s - 1 + previous / (previous - current));  // linear interpolation
    }
    previous = current;
  }
  REQUIRE(crossing_s > 0.0);
  const double c_measured = length_m / (2.0 * crossing_s);
  INFO("wave speed " << c_measured << " m/s, expected " << c_expected << " m/s");
  CHECK(c_measured == Approx(c_expected).epsilon(0.05));
}

TEST_CASE("a block compressed by a rigid plate carries the analytic stress", "[mpm][verification]") {
  // Frictionless table below, frictionless plate above: uniaxial stress sigma = E eps at small
  // strain, whatever nu. The plate's force over the block's area must equal E times the strain.
  SolverConfig config;
  config.dx_m = 0.005;
  config.effects.friction = false;
  config.gravity_m_s2.setZero();     // the plate alone loads the block
  config.grid_damping_per_s = 40.0;  // settles to the static state quickly
  const Material material = SoftMaterial(1e5, 0.3);
  Solver<double> solver(config, {material});
  const double side_m = 0.04;
  const double height_m = 0.04;
  AddBlock<double>({-side_m / 2, -side_m / 2, 0.0}, {side_m / 2, side_m / 2, height_m},
                   config.dx_m, 2, 1000.0, &solver.particles());
  solver.SetTable(0.0);
  const Eigen::Vector3d plate_size(0.2, 0.2, 0.02);
  const double press_m = 0.0008;      // 2 % strain
  const double press_time_s = 0.03;
  RigidMotion plate;
  // Contact acts on grid nodes; the top nodes sit at z = height_m, so the plate starts there.
  const double plate_bottom_start = height_m + 1e-6;
  auto place_plate = [&](double bottom_z, double speed) {
    plate.pose.translation() = Eigen::Vector3d(0, 0, bottom_z + plate_size.z() / 2);
    plate.linear_velocity_m_s = Eigen::Vector3d(0, 0, -speed);
    solver.SetBoard(plate_size, plate);
  };
  const double dt = solver.StableTimestep();
  double t = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  int averaged = 0;
  const double end_s = 0.08;
  while (t < end_s) {
    const double travel = std::min(press_m, press_m * t / press_time_s);
    place_plate(plate_bottom_start - travel, t < press_time_s ? press_m / press_time_s : 0.0);
    const SubstepDiagnostics d = solver.Substep(dt);
    t += dt;
    if (t > end_s - 0.015) {
      force += d.force_on_board_n;
      ++averaged;
    }
  }
  force /= averaged;
  auto& p = solver.particles();
  double strain = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) strain += 1.0 - p.F[8][q];
  strain /= p.size();
  const double stress_measured = force.z() / (side_m * side_m);
  // The block bulges a little: its cross-section grows by about F_xx F_yy.
  double area_scale = 0.0;
  for (std::size_t q = 0; q < p.size(); ++q) area_scale += p.F[0][q] * p.F[4][q];
  area_scale /= p.size();
  // The plate's force spread over the nominal area is the true stress times the area ratio.
  const double stress_analytic = material.youngs_modulus_pa * strain * area_scale;
  INFO("plate stress " << stress_measured << " Pa, E eps " << stress_analytic << " Pa, strain "
                       << strain);
  CHECK(strain == Approx(press_m / height_m).epsilon(0.25));
  CHECK(stress_measured == Approx(stress_analytic).epsilon(0.05));
}

}  // namespace
}  // namespace culinarycut::mpm
