// Same build, same inputs, same thread count -> the same bits; and the thread count does not
// change the result either (colour-blocked P2G and fixed-chunk reductions).
#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {
namespace {

struct Outcome {
  Particles<float> particles;
  std::vector<double> blade_force_z_n;
};

Outcome RunPartialCut(int threads, std::uint64_t seed, const Material& material = testing::SoftMaterial(5e4, 0.3),
                      int thread_limit = 0) {
  SolverConfig config;
  config.dx_m = 0.004;
  config.threads = threads;
  Solver<float> solver(config, {material});
  solver.SetThreadLimit(thread_limit);
  CHECK(solver.team_size() == (thread_limit > 0 ? std::min(threads, thread_limit) : threads));
  const auto shape = MakeFoodShape("apple", 0.4);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.02 - shape->LocalBounds().min().z());
  SamplingOptions sampling;
  sampling.dx_m = config.dx_m;
  sampling.seed = seed;
  SampleFood(*shape, pose, 1000.0, 0, 0, sampling, &solver.particles());
  testing::AddBoardAndTable(&solver);
  testing::CutScenario scenario;
  scenario.start_height_m = 0.056;
  scenario.end_height_m = 0.035;  // halfway into the apple (its top is at 0.0488 m)
  scenario.lift_to_m = 0.056;
  scenario.settle_s = 0.0;
  const testing::CutResult cut = testing::RunCut(scenario, &solver);
  return {solver.particles(), cut.blade_force_z_n};
}

bool SameBits(const Particles<float>& a, const Particles<float>& b) {
  bool same = a.size() == b.size() && a.damage == b.damage && a.blade_side == b.blade_side;
  for (int axis = 0; axis < 3; ++axis) {
    same = same && a.position[axis] == b.position[axis] && a.velocity[axis] == b.velocity[axis];
  }
  for (int k = 0; k < 9; ++k) same = same && a.F[k] == b.F[k] && a.C[k] == b.C[k];
  for (int k = 0; k < 6; ++k) same = same && a.maxwell_stress[k] == b.maxwell_stress[k];
  return same;
}

TEST_CASE("same seed and threads give bitwise identical results", "[mpm][determinism]") {
  const Outcome first = RunPartialCut(1, 7);
  const Outcome second = RunPartialCut(1, 7);
  CHECK(SameBits(first.particles, second.particles));
  CHECK(first.blade_force_z_n == second.blade_force_z_n);
  // A different sampling seed is a different apple.
  CHECK_FALSE(SameBits(first.particles, RunPartialCut(1, 8).particles));
}

TEST_CASE("one and two threads give the same bits", "[mpm][determinism]") {
  const Outcome one = RunPartialCut(1, 7);
  const Outcome two = RunPartialCut(2, 7);
  CHECK(SameBits(one.particles, two.particles));
  CHECK(one.blade_force_z_n == two.blade_force_z_n);
}

TEST_CASE("a thread limit (the machine shared among Steps) changes the team, not the bits", "[mpm][determinism]") {
  const Outcome two = RunPartialCut(2, 7);
  const Outcome limited = RunPartialCut(2, 7, testing::SoftMaterial(5e4, 0.3), 1);
  CHECK(SameBits(two.particles, limited.particles));
  CHECK(two.blade_force_z_n == limited.blade_force_z_n);
}

TEST_CASE("one and two threads give the same bits with a Maxwell branch", "[mpm][determinism][viscoelasticity]") {
  Material material = testing::SoftMaterial(5e4, 0.3);
  material.maxwell_modulus_ratio = 1.0;
  material.maxwell_relaxation_time_s = 0.02;
  const Outcome one = RunPartialCut(1, 7, material);
  const Outcome two = RunPartialCut(2, 7, material);
  CHECK(SameBits(one.particles, two.particles));
  CHECK(one.blade_force_z_n == two.blade_force_z_n);
  // The branch carried stress during the cut.
  double largest_pa = 0.0;
  for (const auto& component : one.particles.maxwell_stress) {
    for (const float value : component) largest_pa = std::max(largest_pa, double(std::abs(value)));
  }
  CHECK(largest_pa > 0.0);
}

}  // namespace
}  // namespace culinarycut::mpm
