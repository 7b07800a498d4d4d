// MLS-MPM throughput (Google Benchmark): particle-steps per second of the full cutting substep
// (damaged corotated stress, two-sided blade contact, force sensing) on a block being cut, at
// 10k, 100k and 1M particles, 1 and 2 threads, float32; with P2G / grid / G2P times as counters.
//
//   build/bench/bench_mpm_throughput --benchmark_counters_tabular=true [--simd=x86-64]  (main: simd_benchmark_main.cc)
//   bench/mpm_throughput_report.py   (runs it and writes docs/benchmarks/mpm_throughput.md)
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

// A block of `particles` (8 per cell at dx = 2 mm) on a board, the knife already in it.
std::unique_ptr<Solver<float>> CuttingBlock(std::int64_t particles, int threads) {
  SolverConfig config;
  config.dx_m = 0.002;
  config.threads = threads;
  Material material = MaterialPreset("cucumber");
  auto solver = std::make_unique<Solver<float>>(config, std::vector<Material>{material});
  // Square footprint, 2 cm high; lattice of 2 x 2 x 2 particles per cell.
  const double spacing = config.dx_m / 2;
  const int nz = 20;
  const int nxy = static_cast<int>(std::round(std::sqrt(double(particles) / nz)));
  const double volume = spacing * spacing * spacing;
  for (int i = 0; i < nxy; ++i) {
    for (int j = 0; j < nxy; ++j) {
      for (int k = 0; k < nz; ++k) {
        solver->particles().Add({float(0.5 + (i - nxy / 2 + 0.5) * spacing),
                                 float((j - nxy / 2 + 0.5) * spacing), float(0.02 + (k + 0.5) * spacing)},
                                float(material.density_kg_m3 * volume), float(volume), 0, 0);
      }
    }
  }
  RigidMotion board;
  board.pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.01);
  solver->SetBoard(Eigen::Vector3d(0.4, 0.3, 0.02), board);
  solver->SetTable(0.0);
  solver->SetKnife(KnifeGeometry{});
  RigidMotion knife;
  knife.pose.linear() << 0, 1, 0, 1, 0, 0, 0, 0, -1;  // blade across x, edge down
  knife.pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.03);  // edge halfway into the block
  knife.linear_velocity_m_s = Eigen::Vector3d(0, 0, -0.05);
  solver->SetKnifeMotion(knife);
  return solver;
}

void BM_CuttingSubstep(benchmark::State& state) {
  const std::int64_t particles = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  auto solver = CuttingBlock(particles, threads);
  const double dt = solver->StableTimestep();
  for (int warmup = 0; warmup < 3; ++warmup) solver->Substep(dt);
  double p2g = 0, grid = 0, g2p = 0, setup = 0;
  for (auto _ : state) {
    const SubstepDiagnostics d = solver->Substep(dt);
    setup += d.setup_ms;
    p2g += d.p2g_ms;
    grid += d.grid_ms;
    g2p += d.g2p_ms;
  }
  const double n = static_cast<double>(solver->particles().size());
  const double iterations = static_cast<double>(state.iterations());
  state.counters["particles"] = n;
  state.counters["threads"] = threads;
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(n * iterations, benchmark::Counter::kIsRate);
  state.counters["setup_ms"] = setup / iterations;
  state.counters["p2g_ms"] = p2g / iterations;
  state.counters["grid_ms"] = grid / iterations;
  state.counters["g2p_ms"] = g2p / iterations;
}

BENCHMARK(BM_CuttingSubstep)
    ->ArgsProduct({{10'000, 100'000, 1'000'000}, {1, 2}})
    ->ArgNames({"particles", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

// The machine's limits for the roofline estimate: memory bandwidth (STREAM-like triad over
// arrays far larger than the caches) and single-precision FMA throughput, both on 2 threads.
void BM_MemoryTriad(benchmark::State& state) {
  const std::size_t n = std::size_t{1} << 25;  // 128 MiB per array
  std::vector<float> a(n, 1.0f), b(n, 2.0f), c(n, 3.0f);
  for (auto _ : state) {
#pragma omp parallel for num_threads(2) schedule(static)
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(n); ++i) a[i] = b[i] + 1.5f * c[i];
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["bytes_per_s"] =
      benchmark::Counter(3.0 * 4.0 * n * state.iterations(), benchmark::Counter::kIsRate);
}

void BM_FmaThroughput(benchmark::State& state) {
  constexpr int kLanes = 64;
  constexpr long kRepeats = 2'000'000;
  for (auto _ : state) {
#pragma omp parallel num_threads(2)
    {
      float acc[kLanes];
      for (int i = 0; i < kLanes; ++i) acc[i] = float(i);
      for (long r = 0; r < kRepeats; ++r) {
#pragma omp simd
        for (int i = 0; i < kLanes; ++i) acc[i] = acc[i] * 0.999999f + 1e-6f;
      }
      benchmark::DoNotOptimize(acc);
    }
  }
  state.counters["flops_per_s"] = benchmark::Counter(2.0 * 2.0 * kLanes * kRepeats * state.iterations(),
                                                     benchmark::Counter::kIsRate);
}

BENCHMARK(BM_MemoryTriad)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
BENCHMARK(BM_FmaThroughput)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);

}  // namespace
}  // namespace culinarycut::mpm
