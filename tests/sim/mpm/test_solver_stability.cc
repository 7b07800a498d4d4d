// Hard cases stay stable (the project's promise that hard cases stay numerically stable): stiff food, a fast knife, nearly
// incompressible flesh, a thin slice, long sawing, a tiny object at a coarse grid. Each must end
// with finite particles, J inside its clamp interval and bounded energy.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {
namespace {

using testing::CutResult;
using testing::CutScenario;

// Kinetic energy no more than the food moving as a whole at 3x the fastest knife speed, and
// elastic energy no more than the whole volume strained by 50 %: anything above is a blow-up.
template <typename Real>
void CheckStable(const CutResult& cut, const Solver<Real>& solver) {
  double mass = 0.0, volume = 0.0;
  for (std::size_t q = 0; q < solver.particles().size(); ++q) {
    mass += solver.particles().mass[q];
    volume += solver.particles().volume[q];
  }
  const Material& material = solver.materials().front();
  INFO("J in [" << cut.j_min << ", " << cut.j_max << "], clamps " << cut.j_clamps << ", max KE "
                << cut.max_kinetic_energy_j << " J, max elastic " << cut.max_elastic_energy_j
                << " J, steps " << cut.steps);
  CHECK(cut.finite);
  CHECK(cut.j_min >= solver.config().j_min - 1e-6);
  CHECK(cut.j_max <= solver.config().j_max + 1e-6);
  CHECK(cut.max_kinetic_energy_j <= 0.5 * mass * std::pow(3.0 * cut.max_knife_speed_m_s, 2));
  CHECK(cut.max_elastic_energy_j <= 0.5 * material.youngs_modulus_pa * 0.25 * volume);
}

TEST_CASE("stiff food (E = 10 MPa) stays stable", "[mpm][stability]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(10e6, 0.3));
  CutScenario scenario;
  scenario.start_height_m = 0.043;
  scenario.end_height_m = 0.036;  // 4 mm into the block: the CFL step of 10 MPa is tiny
  scenario.speed_m_s = 2.0;
  scenario.lift_to_m = 0.043;
  scenario.settle_s = 0.0005;
  CheckStable(testing::RunCut(scenario, &solver), solver);
}

TEST_CASE("a knife at 3.6 m/s stays stable", "[mpm][stability]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.3));
  CutScenario scenario;
  scenario.start_height_m = 0.045;
  scenario.speed_m_s = 3.6;  // the paper's unsafe knife speed
  scenario.lift_speed_m_s = 3.6;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.005;
  CheckStable(testing::RunCut(scenario, &solver), solver);
}

TEST_CASE("nearly incompressible flesh (nu = 0.49) stays stable", "[mpm][stability]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.49));
  CutScenario scenario;
  scenario.start_height_m = 0.045;
  scenario.speed_m_s = 1.0;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.005;
  CheckStable(testing::RunCut(scenario, &solver), solver);
}

TEST_CASE("a thin slice at ratio 0.1 stays stable", "[mpm][stability]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.3));
  CutScenario scenario;
  scenario.cut_x_m = 0.48 + 0.1 * 0.04;  // 4 mm from the block's end: one cell
  scenario.start_height_m = 0.045;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.01;
  CheckStable(testing::RunCut(scenario, &solver), solver);
}

TEST_CASE("50 saw strokes stay stable", "[mpm][stability]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.3));
  CutScenario scenario;
  scenario.start_height_m = 0.042;
  scenario.end_height_m = 0.03;
  scenario.speed_m_s = 0.05;            // 12 mm in 0.24 s ...
  scenario.saw_frequency_hz = 210.0;    // ... with 50 strokes
  scenario.saw_amplitude_m = 0.002;
  scenario.lift_to_m = 0.042;
  scenario.settle_s = 0.005;
  const CutResult cut = testing::RunCut(scenario, &solver);
  CHECK(cut.max_knife_speed_m_s > 2.0);  // the strokes really ran
  CheckStable(cut, solver);
}

TEST_CASE("a strawberry at a coarse grid stays stable", "[mpm][stability]") {
  SolverConfig config;
  config.dx_m = 0.008;  // the strawberry is about 4 cells long
  Material flesh = MaterialPreset("strawberry");
  flesh.youngs_modulus_pa = 5e4;
  Solver<float> solver(config, {flesh});
  const auto shape = MakeFoodShape("strawberry");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.02 - shape->LocalBounds().min().z());
  SamplingOptions sampling;
  sampling.dx_m = config.dx_m;
  SampleFood(*shape, pose, flesh.density_kg_m3, 0, 0, sampling, &solver.particles());
  testing::AddBoardAndTable(&solver);
  CutScenario scenario;
  scenario.start_height_m = 0.05;
  scenario.lift_to_m = 0.05;
  scenario.settle_s = 0.01;
  CheckStable(testing::RunCut(scenario, &solver), solver);
}

}  // namespace
}  // namespace culinarycut::mpm
