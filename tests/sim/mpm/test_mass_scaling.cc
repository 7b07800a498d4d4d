// Mass scaling (solver_config.h): the food's inertia times s, its weight real, the stable step sqrt(s)
// longer; a slow cut must feel the same force as with the real mass.
#include <cmath>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

using testing::AddBlock;
using testing::SoftMaterial;

TEST_CASE("mass scaling lengthens the stable step by its square root", "[mpm][mass_scaling]") {
  SolverModel model;
  model.materials = {SoftMaterial(1e6, 0.3)};
  const double real_dt_s = StableTimestep(model);
  model.config.mass_scaling = 16.0;
  CHECK(StableTimestep(model) == Approx(4.0 * real_dt_s).epsilon(1e-12));
  // The knife's own speed bound does not change: it is about the blade crossing cells.
  CHECK(StableTimestep(model, 1000.0) == Approx(model.config.cfl * model.config.dx_m / 1000.0));
  model.config.mass_scaling = 0.5;
  CHECK_THROWS_WITH(Solver<float>(model.config, model.materials), Catch::Contains("mass_scaling"));
}

TEST_CASE("a block with scaled mass rests on the board with its real weight", "[mpm][mass_scaling]") {
  SolverConfig config;
  config.dx_m = 0.005;
  config.mass_scaling = 25.0;
  // Light damping: it takes g dt c of every node's fall per substep, which would show as missing weight.
  config.grid_damping_per_s = 4.0;
  const double density_kg_m3 = 1000.0;  // the real density
  Solver<double> solver(config, {SoftMaterial(1e5, 0.3)});
  // Sampled with the scaled density, as the world's food model samples it.
  AddBlock<double>({0.48, -0.02, 0.02}, {0.52, 0.02, 0.06}, config.dx_m, 2, config.mass_scaling * density_kg_m3,
                   &solver.particles());
  testing::AddBoardAndTable(&solver);
  double scaled_mass_kg = 0.0;
  for (std::size_t q = 0; q < solver.particles().size(); ++q) scaled_mass_kg += solver.particles().mass[q];
  const double real_weight_n = scaled_mass_kg / config.mass_scaling * 9.81;
  const double dt = solver.StableTimestep();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  int averaged = 0;
  for (double t = 0.0; t < 1.0; t += dt) {
    const SubstepDiagnostics d = solver.Substep(dt);
    if (t > 0.6) {
      force += d.force_on_board_n;
      ++averaged;
    }
  }
  force /= averaged;
  INFO("board force " << force.transpose() << " N, real weight " << real_weight_n << " N");
  CHECK(-force.z() == Approx(real_weight_n).epsilon(0.01));
}

// The blade's mean force over the middle of a slow cut through a soft block.
struct SlowCut {
  double blade_force_n = 0.0;
  int substeps = 0;
};

SlowCut CutWithMassScaling(double mass_scaling) {
  SolverConfig config;
  config.dx_m = 0.004;
  config.mass_scaling = mass_scaling;
  Material flesh = SoftMaterial(2e5, 0.3);
  flesh.fracture_toughness_j_m2 = 100.0;
  Solver<float> solver(config, {flesh});
  AddBlock<float>({0.47, -0.015, 0.02}, {0.53, 0.015, 0.05}, config.dx_m, 2, mass_scaling * 1000.0,
                  &solver.particles());
  testing::AddBoardAndTable(&solver);
  testing::CutScenario scenario;
  scenario.cut_x_m = 0.5005;
  scenario.speed_m_s = 0.05;  // the planner's cutting speeds are 0.02-0.05 m/s
  const testing::CutResult cut = testing::RunCut(scenario, &solver);
  SlowCut result;
  result.blade_force_n = testing::MeanForceWhileDescending(cut, cut.blade_force_z_n, 0.03, 0.045);
  result.substeps = cut.steps;
  return result;
}

TEST_CASE("a slow cut with mass scaling 16 feels the real-mass force in a quarter of the substeps",
          "[mpm][mass_scaling]") {
  const SlowCut real = CutWithMassScaling(1.0);
  const SlowCut scaled = CutWithMassScaling(16.0);
  INFO("blade force " << real.blade_force_n << " N (real mass, " << real.substeps << " substeps) vs "
                      << scaled.blade_force_n << " N (x16, " << scaled.substeps << " substeps)");
  CHECK(scaled.blade_force_n == Approx(real.blade_force_n).epsilon(0.1));
  CHECK(scaled.substeps < 0.3 * real.substeps);
}

}  // namespace
}  // namespace culinarycut::mpm
