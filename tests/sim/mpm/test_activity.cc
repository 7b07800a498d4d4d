// Activity (solver_config.h): food far from the blade that has come to rest freezes, its stress a
// fixed load on the grid, and wakes when the blade comes near. A bar cut near one end must feel the
// same blade force with most of it frozen, and a restored solver must replay bit for bit.
#include <cstdint>
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

using testing::AddBlock;
using testing::SoftMaterial;

constexpr double kDx = 0.004;

SolverConfig BarConfig(double activity_radius_m, int threads = 1) {
  SolverConfig config;
  config.dx_m = kDx;
  config.grid_damping_per_s = 2.0;  // as the server's food: the bar comes to rest
  config.activity.radius_m = activity_radius_m;
  config.activity.sleep_speed_m_s = 0.005;
  config.activity.wake_speed_m_s = 0.015;
  config.threads = threads;
  return config;
}

Material BarMaterial() {
  Material flesh = SoftMaterial(2e5, 0.3);
  flesh.fracture_toughness_j_m2 = 100.0;
  return flesh;
}

// A 16 cm bar on the board, 2 cm square; the blade comes down 2 cm from its left end.
Solver<float> Bar(const SolverConfig& config) {
  Solver<float> solver(config, {BarMaterial()});
  AddBlock<float>({0.40, -0.01, 0.02}, {0.56, 0.01, 0.04}, config.dx_m, 2, 1000.0, &solver.particles());
  testing::AddBoardAndTable(&solver);
  return solver;
}

testing::CutScenario NearTheEnd() {
  testing::CutScenario scenario;
  scenario.cut_x_m = 0.4205;
  scenario.start_height_m = 0.07;
  scenario.speed_m_s = 0.2;
  return scenario;
}

TEST_CASE("activity's radius must keep frozen food clear of the blade's split nodes", "[mpm][activity]") {
  SolverConfig config = BarConfig(4.0 * kDx);
  CHECK_THROWS_WITH(Solver<float>(config, {BarMaterial()}), Catch::Contains("activity.radius_m"));
  config.activity.radius_m = 5.0 * kDx;
  CHECK_NOTHROW(Solver<float>(config, {BarMaterial()}));
  config.activity.wake_speed_m_s = config.activity.sleep_speed_m_s;
  CHECK_THROWS_WITH(Solver<float>(config, {BarMaterial()}), Catch::Contains("activity.wake_speed_m_s"));
}

TEST_CASE("with a radius wider than the food nothing freezes and the cut is the same bits", "[mpm][activity]") {
  Solver<float> off = Bar(BarConfig(0.0));
  Solver<float> wide = Bar(BarConfig(1.0));
  const testing::CutResult a = testing::RunCut(NearTheEnd(), &off);
  const testing::CutResult b = testing::RunCut(NearTheEnd(), &wide);
  REQUIRE(a.steps == b.steps);
  CHECK(std::memcmp(a.blade_force_z_n.data(), b.blade_force_z_n.data(), a.steps * sizeof(double)) == 0);
  CHECK(wide.active_count() == wide.particles().size());
}

TEST_CASE("a bar cut near its end freezes its far part and feels the same blade force", "[mpm][activity]") {
  Solver<float> off = Bar(BarConfig(0.0));
  Solver<float> active = Bar(BarConfig(5.0 * kDx));
  const testing::CutScenario scenario = NearTheEnd();
  const testing::CutResult full = testing::RunCut(scenario, &off);
  const testing::CutResult part = testing::RunCut(scenario, &active);
  REQUIRE(part.finite);
  // How much of the bar was integrated, substep by substep.
  double active_steps = 0.0, min_active = 1.0;
  for (const std::int64_t count : part.active_particles) {
    const double fraction = double(count) / double(active.particles().size());
    active_steps += fraction;
    min_active = std::min(min_active, fraction);
  }
  const double mean_active = active_steps / double(part.active_particles.size());
  const double full_force_n = testing::MeanForceWhileDescending(full, full.blade_force_z_n, 0.024, 0.036);
  const double part_force_n = testing::MeanForceWhileDescending(part, part.blade_force_z_n, 0.024, 0.036);
  INFO("mean active fraction " << mean_active << ", least " << min_active << "; blade force " << part_force_n
                               << " N against " << full_force_n << " N with every particle integrated");
  CHECK(mean_active < 0.6);
  CHECK(part_force_n == Approx(full_force_n).epsilon(0.1));
  CHECK(part.peak_blade_force_n == Approx(full.peak_blade_force_n).epsilon(0.1));
  CHECK(part.side_violations == 0);
  // The far end never moved while frozen: it sits where the bar's own rest left it.
  const auto& p = active.particles();
  for (std::size_t q = active.active_count(); q < p.size(); ++q) {
    CHECK(p.activity[q] == kFrozen);
    CHECK(std::abs(p.velocity[0][q]) + std::abs(p.velocity[1][q]) + std::abs(p.velocity[2][q]) == 0.0f);
    CHECK(std::abs(p.position[2][q] - p.rest_position[2][q]) < 0.001f);  // sagged < 1 mm, no more
  }
}

// Runs the cut's first `substeps` substeps and then `more`, or restores the state after the first
// into a new solver and runs `more` there; returns the final positions.
std::vector<float> PositionsAfter(int substeps, int more, bool restore, int threads = 1) {
  Solver<float> solver = Bar(BarConfig(5.0 * kDx, threads));
  solver.SetKnife(KnifeGeometry{});
  const testing::CutScenario scenario = NearTheEnd();
  const double dt = solver.StableTimestep();
  auto step = [&](Solver<float>* s, int k) {
    RigidMotion motion;
    motion.pose.linear() = testing::BladeAcrossX();
    motion.pose.translation() = Eigen::Vector3d(scenario.cut_x_m, 0.0, scenario.start_height_m - scenario.speed_m_s * k * dt);
    motion.linear_velocity_m_s = Eigen::Vector3d(0.0, 0.0, -scenario.speed_m_s);
    s->SetKnifeMotion(motion);
    s->Substep(dt);
  };
  for (int k = 0; k < substeps; ++k) step(&solver, k);
  Solver<float>* last = &solver;
  Solver<float> restored = Bar(BarConfig(5.0 * kDx, threads));
  if (restore) {
    restored.SetKnife(KnifeGeometry{});
    restored.particles() = solver.particles();
    restored.RestoreSubstepsTaken(solver.substeps_taken());
    restored.RestoreCutProgress(solver.cut_progress());
    last = &restored;
  }
  for (int k = substeps; k < substeps + more; ++k) step(last, k);
  CHECK(last->active_count() < last->particles().size());  // some of it is frozen
  std::vector<float> positions;
  for (int axis = 0; axis < 3; ++axis) {
    positions.insert(positions.end(), last->particles().position[axis].begin(), last->particles().position[axis].end());
  }
  return positions;
}

TEST_CASE("with activity a restored solver replays bit for bit, on any thread count", "[mpm][activity]") {
  // The knife reaches the bar's top after about 0.15 s; restore before, run on into the cut.
  const int before = 2100, after = 1500;
  const std::vector<float> straight = PositionsAfter(before, after, false);
  const std::vector<float> restored = PositionsAfter(before, after, true);
  REQUIRE(straight.size() == restored.size());
  CHECK(std::memcmp(straight.data(), restored.data(), straight.size() * sizeof(float)) == 0);
  const std::vector<float> two_threads = PositionsAfter(before, after, false, 2);
  CHECK(std::memcmp(straight.data(), two_threads.data(), straight.size() * sizeof(float)) == 0);
}

}  // namespace
}  // namespace culinarycut::mpm
