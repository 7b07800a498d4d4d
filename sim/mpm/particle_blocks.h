// Particles grouped by 4-cell grid block for a deterministic parallel P2G: blocks of one of 8
// colours never share a node, so threads scatter them at once without locks, and every node sums
// its contributions in the same order whatever the thread count.
#pragma once

#include <array>
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
  std::vector<std::uint32_t> block_start;                // offsets into `order`; one past the last
  std::array<std::vector<std::uint32_t>, 8> of_colour;   // the non-empty blocks of each colour
  std::vector<std::uint8_t> near_split;                  // 1: its particles can reach a split node

  std::size_t count() const {
    return static_cast<std::size_t>(counts.x()) * counts.y() * counts.z();
  }
  std::size_t Index(int bx, int by, int bz) const {
    return (static_cast<std::size_t>(bx) * counts.y() + by) * counts.z() + bz;
  }
};

// Sorts the particles by the block of their stencil's first node (stable counting sort, in
// parallel; the order depends only on the positions) and lists the blocks by colour.
template <typename Real>
void SortIntoBlocks(const Particles<Real>& particles, Real inv_dx, const Eigen::Vector3i& grid_origin,
                    const Eigen::Vector3i& grid_dims, int threads, ParticleBlocks* blocks);

// Stores the particles in block order (neighbours together in memory, so the transfers stream);
// afterwards `order` is the identity. `spare` lends its arrays' memory and gets the old ones.
template <typename Real>
void StoreInBlockOrder(int threads, ParticleBlocks* blocks, Particles<Real>* particles,
                       Particles<Real>* spare);

// Marks the blocks whose particles touch one of the split nodes (node indices in a grid of
// `grid_dims`): only their particles look up the per-side layers.
void MarkBlocksNearSplit(const std::vector<std::size_t>& split_nodes,
                         const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks);

}  // namespace culinarycut::mpm
