// What one substep adds up (impulses, energies, counts), summed per fixed chunk of nodes or
// particles and then over the chunks in order, so the totals do not depend on the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace culinarycut::mpm {

// Reductions sum fixed chunks in a fixed order; small enough that dynamically scheduled chunks
// balance the threads' load.
inline constexpr std::size_t kChunk = 2048;

// Sums of one grid-update chunk, reduced in chunk order so that totals do not depend on threads.
struct GridTotals {
  Eigen::Vector3d blade_impulse = Eigen::Vector3d::Zero();   // on the food, N s
  Eigen::Vector3d edge_impulse = Eigen::Vector3d::Zero();    // the part of it the edge gave
  Eigen::Vector3d handle_impulse = Eigen::Vector3d::Zero();
  Eigen::Vector3d board_impulse = Eigen::Vector3d::Zero();
  Eigen::Vector3d table_impulse = Eigen::Vector3d::Zero();
  Eigen::Vector3d other_impulse = Eigen::Vector3d::Zero();   // gravity, damping, caps
  double mass = 0.0;                                         // kg on the grid
  double approach_speed_sum = 0.0;                           // over blade-contact nodes, m/s
  double edge_sweep_m2_s = 0.0;  // over edge-contact nodes: share x fill x dx x the edge's speed into the food
  double resistance_sum = 0.0;                               // the sweep's terms, each times its food's k2
  double wave_speed_sum = 0.0;                               // the same, each times its food's wave speed
  std::int64_t speed_caps = 0;

  void Add(const GridTotals& other) {
    blade_impulse += other.blade_impulse;
    edge_impulse += other.edge_impulse;
    handle_impulse += other.handle_impulse;
    board_impulse += other.board_impulse;
    table_impulse += other.table_impulse;
    other_impulse += other.other_impulse;
    mass += other.mass;
    approach_speed_sum += other.approach_speed_sum;
    edge_sweep_m2_s += other.edge_sweep_m2_s;
    resistance_sum += other.resistance_sum;
    wave_speed_sum += other.wave_speed_sum;
    speed_caps += other.speed_caps;
  }
};

struct ParticleTotals {
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d particle_impulse = Eigen::Vector3d::Zero();  // tip force and speed caps
  double kinetic_energy = 0.0;
  double elastic_energy = 0.0;
  double max_speed_sq = 0.0;  // (m/s)^2, of the fastest particle after G2P: a max, so any order gives it
  double j_min = std::numeric_limits<double>::infinity();
  double j_max = -std::numeric_limits<double>::infinity();
  std::int64_t j_clamps = 0;
  std::int64_t speed_caps = 0;
  std::int64_t damaged = 0;

  void Add(const ParticleTotals& other) {
    momentum += other.momentum;
    particle_impulse += other.particle_impulse;
    kinetic_energy += other.kinetic_energy;
    elastic_energy += other.elastic_energy;
    max_speed_sq = std::max(max_speed_sq, other.max_speed_sq);
    j_min = std::min(j_min, other.j_min);
    j_max = std::max(j_max, other.j_max);
    j_clamps += other.j_clamps;
    speed_caps += other.speed_caps;
    damaged += other.damaged;
  }
};

// |v|^2 (m/s)^2 of a particle, in double and in a fixed order. Products of floats are exact in
// double, so a fused multiply-add rounds them as separate operations would: G2P's maximum and
// FastestParticleSpeed's scan give the same bits whatever the compiler contracts.
template <typename Real>
inline double SquaredSpeed(Real vx, Real vy, Real vz) {
  const double x = vx, y = vy, z = vz;
  return (x * x + y * y) + z * z;
}

template <typename Totals>
Totals SumChunks(const std::vector<Totals>& chunks) {
  Totals total;
  for (const Totals& chunk : chunks) total.Add(chunk);
  return total;
}

inline std::size_t ChunkCount(std::size_t n) { return (n + kChunk - 1) / kChunk; }

}  // namespace culinarycut::mpm
