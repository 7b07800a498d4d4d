// Each food touches the colliders with its own material: board friction and knife speed resistance
// come from the food at the contact, not from the scene's first material.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/physics/speed_resistance.h"

namespace culinarycut::mpm {
namespace {

using testing::AddBlock;
using testing::AddBoardAndTable;
using testing::SoftMaterial;

Material Slippery() {
  Material material = SoftMaterial(1e5);
  material.name = "slippery";
  material.board_friction_coefficient = 0.05;
  return material;
}

Material Grippy() {
  Material material = SoftMaterial(1e5);
  material.name = "grippy";
  material.board_friction_coefficient = 0.8;
  return material;
}

SolverConfig SmallConfig() {
  SolverConfig config;
  config.dx_m = 0.005;
  config.threads = 1;
  return config;
}

// Mean x velocity of one object's particles (m/s).
double MeanVelocityX(const Particles<float>& p, std::uint16_t object) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    if (p.object[q] != object) continue;
    sum += p.velocity[0][q];
    ++count;
  }
  return sum / count;
}

// Blocks (one per material, 12 cm apart along y) sliding along +x at 0.5 m/s on the board for 50 ms.
std::vector<double> SlideBlocks(const std::vector<Material>& materials, const std::vector<double>& y_m) {
  Solver<float> solver(SmallConfig(), materials);
  for (std::size_t b = 0; b < y_m.size(); ++b) {
    AddBlock<float>({0.45, y_m[b] - 0.02, 0.0205}, {0.49, y_m[b] + 0.02, 0.0405}, 0.005, 2, 1000.0,
                    &solver.particles(), static_cast<std::uint16_t>(b), static_cast<std::uint16_t>(b));
  }
  for (auto& v : solver.particles().velocity[0]) v = 0.5f;
  AddBoardAndTable(&solver);
  const double dt = solver.StableTimestep();
  for (double t = 0.0; t < 0.05; t += dt) solver.Substep(dt);
  std::vector<double> velocities;
  for (std::size_t b = 0; b < y_m.size(); ++b) velocities.push_back(MeanVelocityX(solver.particles(), b));
  return velocities;
}

}  // namespace

TEST_CASE("two foods of different materials on one board each keep their own friction", "[mpm][contact]") {
  const double slippery_alone = SlideBlocks({Slippery()}, {-0.06})[0];
  const double grippy_alone = SlideBlocks({Grippy()}, {0.06})[0];
  const std::vector<double> together = SlideBlocks({Slippery(), Grippy()}, {-0.06, 0.06});
  CHECK(together[0] == Approx(slippery_alone).epsilon(1e-4));
  CHECK(together[1] == Approx(grippy_alone).epsilon(1e-4));
  // The friction matters: Coulomb deceleration mu g over 50 ms is 0.02 vs 0.39 m/s.
  CHECK(slippery_alone - grippy_alone > 0.2);
}

TEST_CASE("the knife's speed resistance is the food it cuts, not the scene's first", "[mpm][contact]") {
  Material stiff = SoftMaterial(4e5);
  stiff.name = "stiff";
  Material soft = SoftMaterial(5e4);
  // The knife descends through a block of `cut` at x = 0.5; a block of `other` lies 20 cm away.
  // One time step for every run: the stiff material's (the shorter).
  const double dt = mpm::StableTimestep(SolverModel{SmallConfig(), {stiff}}) * 0.004 / SmallConfig().dx_m;
  auto factors = [dt](const std::vector<Material>& materials, std::uint16_t cut, bool other_block) {
    SolverConfig config = SmallConfig();
    config.dx_m = 0.004;
    Solver<float> solver(config, materials);
    AddBlock<float>({0.47, -0.015, 0.02}, {0.53, 0.015, 0.05}, config.dx_m, 2, 1000.0, &solver.particles(), 0, cut);
    if (other_block) {
      AddBlock<float>({0.27, -0.015, 0.02}, {0.33, 0.015, 0.05}, config.dx_m, 2, 1000.0, &solver.particles(), 1,
                      static_cast<std::uint16_t>(1 - cut));
    }
    AddBoardAndTable(&solver);
    solver.SetKnife(KnifeGeometry{});
    RigidMotion motion;
    motion.pose.linear() = testing::BladeAcrossX();
    motion.linear_velocity_m_s = Eigen::Vector3d(0, 0, -0.5);
    std::vector<double> result;
    for (double height = 0.06; height > 0.03; height -= 0.5 * dt) {
      motion.pose.translation() = Eigen::Vector3d(0.5, 0.0, height);
      solver.SetKnifeMotion(motion);
      result.push_back(solver.Substep(dt).knife_speed_factor);
    }
    return result;
  };
  // The soft block is cut; the stiff one, material 0, is the scene's first.
  const std::vector<double> mixed = factors({stiff, soft}, 1, true);
  const std::vector<double> soft_alone = factors({soft}, 0, false);
  const std::vector<double> stiff_alone = factors({stiff}, 0, false);
  REQUIRE(mixed.size() == soft_alone.size());
  double worst = 0.0, stiff_gap = 0.0;
  for (std::size_t s = 0; s < mixed.size(); ++s) {
    worst = std::max(worst, std::abs(mixed[s] - soft_alone[s]));
    stiff_gap = std::max(stiff_gap, std::abs(stiff_alone[s] - soft_alone[s]));
  }
  CHECK(*std::min_element(soft_alone.begin(), soft_alone.end()) < 1.0);  // the knife did meet resistance
  CHECK(worst < 1e-6);
  CHECK(stiff_gap > 1e-4);  // and the stiff food would have resisted differently (k2 8x larger)
}

// The slow-down a descent through a firm block adds up, sum(k2 c-hat dt) (s/m): the knife edge-first
// from 4 mm above the block to 14 mm into it at `speed_m_s`, one substep of `substep_s` per knife pose.
double DescentResistance(const Material& firm, double speed_m_s, double substep_s) {
  SolverConfig config = SmallConfig();
  config.dx_m = 0.004;
  Solver<float> solver(config, {firm});
  AddBlock<float>({0.47, -0.015, 0.02}, {0.53, 0.015, 0.05}, config.dx_m, 2, 1000.0, &solver.particles(), 0, 0);
  AddBoardAndTable(&solver);
  solver.SetKnife(KnifeGeometry{});
  RigidMotion motion;
  motion.pose.linear() = testing::BladeAcrossX();
  motion.linear_velocity_m_s = Eigen::Vector3d(0, 0, -speed_m_s);
  double sum = 0.0;
  for (double height = 0.054; height > 0.036; height -= speed_m_s * substep_s) {
    motion.pose.translation() = Eigen::Vector3d(0.5, 0.0, height);
    solver.SetKnifeMotion(motion);
    sum += SubstepResistance(solver.Substep(substep_s));
  }
  return sum;
}

// A substep that keeps the knife's 0.2 m/s descent stable on the block's 4 mm grid.
double FirmSubstep(const Material& firm) {
  return mpm::StableTimestep(SolverModel{SmallConfig(), {firm}}) * 0.004 / SmallConfig().dx_m;
}

TEST_CASE("the knife's speed resistance per second does not depend on the substep", "[mpm][contact]") {
  // The same descent at 0.2 m/s with substeps dt and 2 dt. Taking c-hat at the grid speed dx / dt (the
  // paper's normalisation) makes the slow-down 2.9x as large at 2 dt, and summing the edge nodes' approach
  // speeds at a fixed grid speed still 1.45x; the edge's sweep (engaged length times the edge's speed) is
  // the same at both.
  const Material firm = SoftMaterial(4e5);
  const double dt = FirmSubstep(firm);
  const double fine = DescentResistance(firm, 0.2, dt);
  const double coarse = DescentResistance(firm, 0.2, 2.0 * dt);
  INFO("sum k2 c-hat dt: " << fine << " s/m at dt, " << coarse << " s/m at 2 dt");
  CHECK(fine > 0.0);
  CHECK(coarse / fine < 1.02);
  CHECK(coarse / fine > 1.0 / 1.02);
}

TEST_CASE("the knife's speed resistance is quadratic: the slow-down over a depth does not depend on the speed",
          "[mpm][contact]") {
  // du/dt = -k2 c-hat u with c-hat proportional to the edge's speed: over the same depth a knife twice as
  // fast spends half the time at twice the contact strength, so it loses the same fraction of its speed.
  const Material firm = SoftMaterial(4e5);
  const double dt = FirmSubstep(firm);
  const double fast = DescentResistance(firm, 0.2, dt);
  const double slow = DescentResistance(firm, 0.1, dt);
  INFO("sum k2 c-hat dt over the descent: " << fast << " s/m at 0.2 m/s, " << slow << " s/m at 0.1 m/s");
  CHECK(fast > 0.0);
  CHECK(slow / fast > 0.9);
  CHECK(slow / fast < 1.1);
}

}  // namespace culinarycut::mpm
