// Hertz contact through the MPM solver: an elastic sphere (R 2 cm, E 0.1 MPa, nu 0.3) lies on the table
// and a rigid plate presses it slowly (20 mm/s) from 2 dx above its top to 10 % of R at each contact, with
// no gravity and no friction. Each contact should carry F = 4/3 E* sqrt(R) delta^(3/2) (E* = E / (1 - nu^2)
// against a rigid flat), delta being half the plate's travel past the sphere's top. Prints one JSON object
// with the plate's force (mean over 2 ms windows) against Hertz at each tenth of the travel, where the
// plate first feels the sphere, and the J clamps; bench/hertz_contact_report.py writes the page.
//
//   bench_hertz_contact DX_M
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "sim/mpm/solver.h"

using namespace culinarycut::mpm;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: bench_hertz_contact DX_M   (grid spacing, m, in [0.001, 0.01])\n";
    return 2;
  }
  const double dx_m = std::stod(argv[1]);
  if (!(dx_m >= 0.001 && dx_m <= 0.01)) {
    std::cerr << "bench_hertz_contact: DX_M must lie in [0.001, 0.01] m\n";
    return 2;
  }
  const double radius_m = 0.02, youngs_pa = 1e5, nu = 0.3, density_kg_m3 = 1000.0;
  const double speed_m_s = 0.02;                      // slow against the sphere's sound (R / c ~ 2 ms)
  const double start_gap_m = 2.0 * dx_m;              // above the sphere's top at first: past its nodes' reach
  const double max_travel_m = 2.0 * 0.1 * radius_m;   // 10 % of R at each contact
  const double window_s = 0.002;

  SolverConfig config;
  config.dx_m = dx_m;
  config.effects.friction = false;
  config.gravity_m_s2.setZero();
  Material material = MaterialPreset("generic");
  material.name = "hertz sphere";
  material.youngs_modulus_pa = youngs_pa;
  material.poisson_ratio = nu;
  material.density_kg_m3 = density_kg_m3;
  material.yield_stress_pa = 0.0;
  Solver<double> solver(config, {material});
  // 2 x 2 x 2 particles per cell on a lattice, inside the sphere, which touches the table at z = 0.
  const double spacing_m = dx_m / 2.0;
  const int n = static_cast<int>(std::ceil(radius_m / spacing_m));
  const double volume_m3 = spacing_m * spacing_m * spacing_m;
  for (int i = -n; i < n; ++i) {
    for (int j = -n; j < n; ++j) {
      for (int k = -n; k < n; ++k) {
        const Eigen::Vector3d x = spacing_m * (Eigen::Vector3d(i, j, k).array() + 0.5).matrix();
        if (x.norm() > radius_m) continue;
        solver.particles().Add({x.x(), x.y(), x.z() + radius_m}, density_kg_m3 * volume_m3, volume_m3, 0, 0);
      }
    }
  }
  solver.SetTable(0.0);
  const Eigen::Vector3d plate_size_m(0.2, 0.2, 0.02);
  const double top_m = 2.0 * radius_m;
  const double e_star_pa = youngs_pa / (1.0 - nu * nu);
  const double dt_s = solver.StableTimestep();

  nlohmann::json points = nlohmann::json::array();
  double first_force_indentation_m = std::nan("");
  std::int64_t j_clamps = 0, substeps = 0;
  double j_min = 1.0, window_impulse = 0.0, window_time = 0.0, t = 0.0;
  double next_report_m = 0.1 * max_travel_m;
  const auto started = std::chrono::steady_clock::now();
  while (true) {
    const double bottom_m = top_m + start_gap_m - speed_m_s * t;
    const double travel_m = top_m - bottom_m;
    if (travel_m > max_travel_m + 1e-12) break;
    RigidMotion plate;
    plate.pose.translation() = Eigen::Vector3d(0.0, 0.0, bottom_m + 0.5 * plate_size_m.z());
    plate.linear_velocity_m_s = Eigen::Vector3d(0.0, 0.0, -speed_m_s);
    solver.SetBoard(plate_size_m, plate);
    const SubstepDiagnostics d = solver.Substep(dt_s);
    t += dt_s;
    ++substeps;
    j_clamps += d.j_clamps;
    j_min = std::min(j_min, d.j_min);
    const double force_n = d.force_on_board_n.z();
    if (std::isnan(first_force_indentation_m) && force_n > 1e-3) first_force_indentation_m = 0.5 * travel_m;
    window_impulse += force_n * dt_s;
    window_time += dt_s;
    if (window_time >= window_s) {
      if (travel_m >= next_report_m) {
        const double delta_m = 0.5 * travel_m;
        points.push_back({{"indentation_m", delta_m},
                          {"force_n", window_impulse / window_time},
                          {"hertz_n", 4.0 / 3.0 * e_star_pa * std::sqrt(radius_m) * std::pow(delta_m, 1.5)}});
        next_report_m += 0.1 * max_travel_m;
      }
      window_impulse = window_time = 0.0;
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  nlohmann::json out = {{"dx_m", dx_m}, {"radius_m", radius_m}, {"youngs_pa", youngs_pa}, {"poisson_ratio", nu},
                        {"plate_speed_m_s", speed_m_s}, {"particles", solver.particles().size()},
                        {"substeps", substeps}, {"wall_s", wall_s}, {"points", points},
                        {"first_force_indentation_m", first_force_indentation_m},
                        {"j_clamps", j_clamps}, {"j_min", j_min}};
  std::cout << out.dump() << "\n";
  return 0;
}
