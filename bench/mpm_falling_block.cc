// MLS-MPM at equal work with its peers (Google Benchmark): particle-steps per second of an elastic
// block falling onto a floor: no knife, no board, no damage, no plasticity, no friction; the scene
// bench/peers/taichi_falling_block.py and warp_falling_block.py simulate with the same settings,
// which this benchmark reports as counters (bench/mpm_peers.py passes them on).
//
//   build/bench/bench_mpm_falling_block --benchmark_counters_tabular=true [--simd=x86-64]
//   bench/mpm_peers.py   (runs it and the peers, writes docs/benchmarks/mpm_peers.md)
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

constexpr double kDx_m = 0.002;
constexpr int kLatticePerCellAxis = 2;  // 2 x 2 x 2 = 8 particles per cell
constexpr double kGap_m = 0.002;        // the block's underside above the floor at the start
// Falling at the speed of a drop from 5 cm (sqrt(2 g h) = 0.99 m/s): it lands within the timed
// steps, so the centre-of-mass check covers elasticity and the floor, not just free fall.
constexpr double kDropSpeed_m_s = 1.0;
constexpr int kWarmupSteps = 3;  // the peers' warm-up too: their kernels compile on the first step
// Every run is the same number of steps, so the peers can run exactly as many and the block's
// centre of mass must end where ours does (1.8 ms of simulated time at the CFL step).
constexpr int kTimedSteps = 300;

// Particles per side of the cube closest to `particles`.
int SideParticles(std::int64_t particles) {
  return static_cast<int>(std::lround(std::cbrt(static_cast<double>(particles))));
}

// A cube of side^3 particles on a lattice of spacing dx / 2, its underside kGap_m above the floor
// at z = 0, moving down at kDropSpeed_m_s.
std::unique_ptr<Solver<float>> FallingBlock(int side, int threads) {
  SolverConfig config;
  config.dx_m = kDx_m;
  config.threads = threads;
  // Equal work with the peers' plain elastic MLS-MPM: no plastic return, no damage, a frictionless
  // floor (only the approaching normal velocity removed), no impulse bookkeeping.
  config.effects.plasticity = false;
  config.effects.damage = false;
  config.effects.friction = false;
  config.effects.force_sensing = false;
  config.effects.two_sided_blade = false;
  const Material material = MaterialPreset("cucumber");
  auto solver = std::make_unique<Solver<float>>(config, std::vector<Material>{material});
  const double spacing = kDx_m / kLatticePerCellAxis;
  const double volume = spacing * spacing * spacing;
  Particles<float>& p = solver->particles();
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      for (int k = 0; k < side; ++k) {
        p.Add({float((i + 0.5) * spacing), float((j + 0.5) * spacing), float(kGap_m + (k + 0.5) * spacing)},
              float(material.density_kg_m3 * volume), float(volume), 0, 0);
      }
    }
  }
  for (float& v : p.velocity[2]) v = float(-kDropSpeed_m_s);
  solver->SetTable(0.0);
  return solver;
}

// The block's centre of mass height (m); every particle has the same mass.
double CentreHeight(const Particles<float>& p) {
  double sum = 0.0;
  for (const float z : p.position[2]) sum += z;
  return sum / static_cast<double>(p.size());
}

void BM_FallingBlock(benchmark::State& state) {
  const int side = SideParticles(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  auto solver = FallingBlock(side, threads);
  const double dt = solver->StableTimestep();
  const double start_height = CentreHeight(solver->particles());
  for (int warmup = 0; warmup < kWarmupSteps; ++warmup) solver->Substep(dt);
  for (auto _ : state) solver->Substep(dt);
  const Material& material = solver->materials()[0];
  const double n = static_cast<double>(solver->particles().size());
  state.counters["particles"] = n;
  state.counters["threads"] = threads;
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(n * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  // The settings, for the peers to take over exactly.
  state.counters["side_particles"] = side;
  state.counters["particles_per_cell"] = std::pow(kLatticePerCellAxis, 3);
  state.counters["dx_m"] = kDx_m;
  state.counters["dt_s"] = dt;
  state.counters["cfl"] = solver->config().cfl;
  state.counters["youngs_modulus_pa"] = material.youngs_modulus_pa;
  state.counters["poisson_ratio"] = material.poisson_ratio;
  state.counters["density_kg_m3"] = material.density_kg_m3;
  state.counters["gravity_m_s2"] = -solver->config().gravity_m_s2.z();
  state.counters["gap_m"] = kGap_m;
  state.counters["drop_speed_m_s"] = kDropSpeed_m_s;
  state.counters["warmup_steps"] = kWarmupSteps;
  state.counters["steps"] = static_cast<double>(state.iterations());
  // What the physics did: how far the centre of mass fell over the warm-up and timed steps (m).
  state.counters["com_drop_m"] = start_height - CentreHeight(solver->particles());
}

BENCHMARK(BM_FallingBlock)
    ->ArgsProduct({{10'000, 100'000}, {1, 2}})
    ->ArgNames({"particles", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(kTimedSteps);

}  // namespace
}  // namespace culinarycut::mpm
