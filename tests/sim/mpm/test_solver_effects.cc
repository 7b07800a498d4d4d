// Every effect can be switched off, and switching it off does what it says.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"

namespace culinarycut::mpm {
namespace {

// A partial cut (the edge 1 cm into a block) with the given effects; returns the solver.
std::unique_ptr<Solver<float>> PartialCut(const Effects& effects, testing::CutResult* result,
                                          double yield_stress_pa = 0.0) {
  SolverConfig config;
  config.dx_m = 0.004;
  config.effects = effects;
  Material material = testing::SoftMaterial(5e4, 0.3);
  material.yield_stress_pa = yield_stress_pa;
  auto solver = std::make_unique<Solver<float>>(config, std::vector<Material>{material});
  testing::AddBlock<float>({0.48, -0.01, 0.02}, {0.52, 0.01, 0.04}, config.dx_m, 2, 1000.0,
                           &solver->particles());
  testing::AddBoardAndTable(solver.get());
  testing::CutScenario scenario;
  scenario.start_height_m = 0.044;
  scenario.end_height_m = 0.03;
  scenario.lift_to_m = 0.044;
  scenario.settle_s = 0.0;
  *result = testing::RunCut(scenario, solver.get());
  return solver;
}

TEST_CASE("force sensing off measures nothing and changes nothing else", "[mpm][effects]") {
  testing::CutResult with_sensing, without_sensing;
  const auto sensed = PartialCut(Effects{}, &with_sensing);
  Effects effects;
  effects.force_sensing = false;
  const auto unsensed = PartialCut(effects, &without_sensing);
  CHECK(with_sensing.peak_blade_force_n > 0.0);
  CHECK(without_sensing.peak_blade_force_n == 0.0);
  CHECK(sensed->particles().position[2] == unsensed->particles().position[2]);
  CHECK(sensed->particles().damage == unsensed->particles().damage);
}

TEST_CASE("plasticity off leaves no plastic strain", "[mpm][effects]") {
  testing::CutResult cut;
  const auto plastic = PartialCut(Effects{}, &cut, 2e3);  // a low yield stress: it flows
  double flowed = 0.0;
  for (float alpha : plastic->particles().plastic_strain) flowed += alpha;
  CHECK(flowed > 0.0);
  Effects effects;
  effects.plasticity = false;
  const auto elastic = PartialCut(effects, &cut, 2e3);
  for (float alpha : elastic->particles().plastic_strain) CHECK(alpha == 0.0f);
}

TEST_CASE("friction and the two-sided blade can be switched off", "[mpm][effects]") {
  testing::CutResult with_friction, frictionless;
  const auto rough = PartialCut(Effects{}, &with_friction);
  Effects effects;
  effects.friction = false;
  const auto smooth = PartialCut(effects, &frictionless);
  CHECK(rough->particles().position[2] != smooth->particles().position[2]);

  effects = Effects{};
  effects.two_sided_blade = false;
  testing::CutResult one_sided;
  const auto solver = PartialCut(effects, &one_sided);
  for (auto side : solver->particles().blade_side) CHECK(side == 0);  // no side labels at all
  CHECK(one_sided.finite);
}

}  // namespace
}  // namespace culinarycut::mpm
