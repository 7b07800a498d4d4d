// What the stages of one substep share (solver.cc orchestrates them; solver_*.cc hold them): the
// bounded grid box, the reused scratch arrays and the numbers derived once per substep.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/kernels/node_momentum.h"
#include "sim/mpm/kernels/particle_blocks.h"
#include "sim/mpm/kernels/substep_totals.h"
#include "sim/mpm/physics/contact_materials.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {

// c-hat = (edge nodes' approach speeds, scaled to the reference grid) / (0.35 x a grid speed) (paper).
constexpr double kContactStrengthScale = 0.35;

// Materials a solver with a Maxwell branch may have (G2P keeps their branches in a table on the stack).
constexpr std::size_t kMaxMaxwellMaterials = 16;

// How far ahead (particles) the stress and G2P loops prefetch the 3x3 fields: their 18 streams of F
// and C are more than the hardware prefetcher follows. Prefetching past an array's end is harmless.
constexpr std::size_t kPrefetchAhead = 128;
// G2P prefetches only for this many particles and more: fewer keep their fields in the caches.
constexpr std::size_t kPrefetchFromParticles = 32768;

// Nodes split by blade side only once the edge is this far below them (in dx); closer to the edge
// the node is pushed by the edge itself (edge_resistance.h).
constexpr double kSplitAboveEdgeCells = 0.5;

// One grid node: (momentum x, y, z, mass) after P2G, (velocity, mass) after the grid update. One
// 4-vector: a transfer adds to it with one SIMD operation and touches one cache line.
template <typename Real>
using GridNode = Vector4<Real>;

// The bounded grid box: nodes (origin + (i, j, k)) * dx for i < dims.x() etc. Near the blade,
// "split" nodes keep one layer per blade side (CPIC-style) so the sides never share momentum.
template <typename Real>
struct Solver<Real>::Grid {
  Eigen::Vector3i origin = Eigen::Vector3i::Zero();  // global index of node (0, 0, 0)
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<GridNode<Real>> node;
  std::vector<std::int32_t> split_slot;              // -1, or this node's slot in the layers
  std::vector<std::size_t> split_nodes;              // node index of each slot
  std::array<std::vector<GridNode<Real>>, 2> layer;  // [side: 0 negative, 1 positive][slot]

  std::size_t size() const {
    return static_cast<std::size_t>(dims.x()) * dims.y() * dims.z();
  }
  std::size_t Index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * dims.y() + j) * dims.z() + k;
  }
  std::size_t stride_i() const { return static_cast<std::size_t>(dims.y()) * dims.z(); }
  std::size_t stride_j() const { return static_cast<std::size_t>(dims.z()); }
  Eigen::Vector3d Position(int i, int j, int k, double dx_m) const {
    return Eigen::Vector3d((origin.x() + i) * dx_m, (origin.y() + j) * dx_m, (origin.z() + k) * dx_m);
  }
};

// Scratch arrays reused from substep to substep (no allocation, no page faults in the hot path).
template <typename Real>
struct Solver<Real>::Workspace {
  ParticleBlocks blocks;
  Particles<Real> reorder_spare;             // memory the block-order reorder permutes into
  std::vector<NodeMomentum<Real>> node_momentum;  // P2G: what each particle adds to its nodes
  std::vector<double> elastic_energy_of_chunk;
  std::vector<GridTotals> grid_chunks;
  std::vector<ParticleTotals> particle_chunks;
  std::uint64_t substeps_since_reorder = 0;
  // Setup: bounds (low x y z, high x y z, finite) and momentum of each fixed particle chunk.
  std::vector<std::array<Real, 7>> chunk_bounds;
  std::vector<Eigen::Vector3d> momentum_of_chunk;
  std::vector<CutCounts> cut_counts_of_chunk;  // side labels and cut records per particle chunk
  // Split-node candidates in global node indices (they depend on the knife only), lexicographic.
  std::vector<Eigen::Vector3i> split_candidates;
  Eigen::Vector3i candidate_low = Eigen::Vector3i::Zero();   // the global node box searched
  Eigen::Vector3i candidate_high = -Eigen::Vector3i::Ones();  // (inclusive; empty: low > high)
  bool reorder_now = false;                  // this substep stores the particles in block order
  // P2G without colour barriers: a block waits only for the stress chunks holding its particles
  // and for its lower-colour neighbours (flags hold the substep's stamp once done).
  std::vector<std::uint32_t> scatter_list;   // the non-empty blocks, colour by colour
  std::vector<std::uint32_t> block_done;     // per block: stamp once scattered
  std::vector<std::uint32_t> chunk_done;     // per stress chunk: stamp once computed
  std::atomic<std::int64_t> next_item{0};    // the next stress chunk or block to take
  std::atomic<int> sorted_threads{0};        // threads whose share of the block order is written
  std::uint32_t stamp = 0;
  ContactMaterials contact_materials;        // each food's friction and speed resistance at the colliders
  bool contact_materials_ready = false;
};

// What the frozen particles (SolverConfig::activity) add to the grid every substep: their mass
// and their stress's force on the nodes of their own box, rebuilt whenever the frozen set changes.
template <typename Real>
struct Solver<Real>::FrozenLoad {
  bool valid = false;                             // built from the particles frozen now
  Eigen::Vector3i origin = Eigen::Vector3i::Zero();  // global index of node (0, 0, 0)
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<Vector4<Real>> node;                // (force x, y, z (N), mass (kg))
  std::vector<std::uint8_t> pushed;               // 1: moving food pushed this node past the wake speed
  bool any_pushed = false;
  double elastic_energy_j = 0.0;                  // the frozen particles' (it does not change)
};

// What one substep's team shares beyond the workspace: results the stages hand on, the first
// error (thrown after the parallel region), and the stage clock.
struct SubstepShared {
  std::exception_ptr error;
  bool failed = false;
  std::exception_ptr box_error;  // the grid box's, which every thread finds alike
  Eigen::Vector3d momentum_before = Eigen::Vector3d::Zero();
  double elastic_energy_j = 0.0;
  double stage_ms[4] = {0.0, 0.0, 0.0, 0.0};  // setup, P2G, grid, G2P
  std::chrono::steady_clock::time_point g2p_start;
};

// The numbers one substep derives from the config, the time step and the knife, once.
struct SubstepContext {
  double dt_s = 0.0;
  double dx_m = 0.0;
  bool knife_on = false;
  bool split_on = false;            // the two-sided blade is simulated this substep
  int cut_index = 0;                // the cut particles record into (cut_record.h)
  double band_m = 0.0;              // damage band around the edge, rescaled with dx (paper)
  double v_threshold_m_s = 0.0;     // approach speed above which damage grows (paper)
  double blade_half_m = 0.0;        // half the blade's effective thickness
  // Nodes this close to the blade's mid-plane, at or above the edge, are split by side.
  double split_half_width_m = 0.0;
  double half_length_m = 0.0;       // half the blade's length
  double blade_height_m = 0.0;      // spine to edge
  // A particle's stencil reaches 1.5 cells along each grid axis: 1.5 sqrt(3) dx in any frame.
  double stencil_reach_m = 0.0;
};

// What the grid update hands to G2P: the contact strength and the damage and tip-force gates.
struct ContactState {
  GridTotals totals;
  double c_hat = 0.0;
  bool damage_gate = false;
  bool tip_on = false;
};

}  // namespace culinarycut::mpm
