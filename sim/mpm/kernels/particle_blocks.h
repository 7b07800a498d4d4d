// Particles grouped by 4-cell grid block for a deterministic parallel P2G: blocks of one of 8
// colours never share a node, so threads scatter them at once without locks, and every node sums
// its contributions in the same order (colour by colour) whatever the thread count.
//
// The functions marked "team" are called by every thread of an OpenMP team (or outside any
// parallel region, by one thread): they share their work out with orphaned work-sharing
// constructs and end with a barrier.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/particles.h"

namespace culinarycut::mpm {

inline constexpr int kBlockCells = 4;  // block edge (cells); a stencil spans 3 nodes

struct ParticleBlocks {
  Eigen::Vector3i counts = Eigen::Vector3i::Zero();      // blocks along each axis
  std::vector<std::uint32_t> block_of;                   // block of each stored particle
  std::vector<std::uint32_t> block_of_spare;             // memory for reordering block_of
  std::vector<std::uint32_t> order;                      // particles sorted by block (stable)
  std::vector<std::uint32_t> order_spare;                // memory for the identity after a reorder
  std::vector<std::uint32_t> block_start;                // offsets into `order`; one past the last
  std::vector<std::uint32_t> by_colour;                  // the non-empty blocks, colour 0 first
  std::vector<std::vector<std::uint32_t>> thread_counts; // the sort's histograms, per thread
  std::vector<std::uint8_t> near_split;                  // 1: its particles can reach a split node

  std::size_t count() const {
    return static_cast<std::size_t>(counts.x()) * counts.y() * counts.z();
  }
  std::size_t Index(int bx, int by, int bz) const {
    return (static_cast<std::size_t>(bx) * counts.y() + by) * counts.z() + bz;
  }
  static int Colour(int bx, int by, int bz) { return (bx & 1) | ((by & 1) << 1) | ((bz & 1) << 2); }
};

// Blocks along each axis for a grid of `grid_dims` nodes.
inline Eigen::Vector3i BlockCounts(const Eigen::Vector3i& grid_dims) {
  return (grid_dims.array() + kBlockCells - 1) / kBlockCells;
}

// The stable counting sort of the particles by the block of their stencil's first node (the order
// depends only on the positions), in three steps:
// Team: each thread counts the blocks of its share of the first `count` particles (`block_of` must
// have an entry for each and `thread_counts` one vector per thread); ends with a barrier.
template <typename Real>
void CountBlocks(const Particles<Real>& particles, std::size_t count, Real inv_dx, const Eigen::Vector3i& grid_origin,
                 const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks);
// One thread of the team that counted (inside its parallel region): sets `counts`, the blocks'
// offsets and the non-empty blocks by colour.
void ListBlocks(const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks);
// Team: each thread places its share into `order` (one entry per particle). With `threads_done`
// (zero before), no barrier at the end: each thread adds 1 to it (release) once its share is
// written, and whoever reads `order` waits until it equals the team size.
void PlaceInBlocks(std::size_t particles, ParticleBlocks* blocks,
                   std::atomic<int>* threads_done = nullptr);

// Sizes the spare arrays StoreInBlockOrder permutes into (by one thread, before the team).
template <typename Real>
void SizeBlockOrderSpares(ParticleBlocks* blocks, const Particles<Real>& particles,
                          Particles<Real>* spare);

// Team: stores the particles in block order (neighbours together in memory, so the transfers
// stream); afterwards `order` is the identity. `spare` lends its arrays' memory and gets the old
// ones.
template <typename Real>
void StoreInBlockOrder(ParticleBlocks* blocks, Particles<Real>* particles, Particles<Real>* spare);

// Marks the blocks whose particles touch one of the split nodes (node indices in a grid of
// `grid_dims`): only their particles look up the per-side layers. Reads no other field of
// `blocks`, so it may run beside ListBlocks.
void MarkBlocksNearSplit(const std::vector<std::size_t>& split_nodes,
                         const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks);

}  // namespace culinarycut::mpm
