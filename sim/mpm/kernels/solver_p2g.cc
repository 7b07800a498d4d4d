// P2G, part 2: each particle's mass and APIC momentum to its 27 grid nodes, block by block in
// colour order (blocks of one colour never share a node: no locks, and the same sums on any
// threads). One queue hands out the stress chunks (part 1) and then the blocks, colour 0 first;
// instead of a barrier after the stress and after each colour, a block waits only for what it
// needs: the stress chunks holding its particles and its neighbours of lower colour. So every
// node still sums its contributions colour by colour, in the same order on any thread count.
#include <algorithm>
#include <atomic>
#include <thread>

#include <omp.h>

#include "sim/mpm/kernels/solver_internals.h"
#include "sim/mpm/kernels/transfer_stencil.h"

namespace culinarycut::mpm {
namespace {

// Adds w_ijk (at_first_node + i step_i + j step_j + k step_k) to the 27 nodes; `node_at(row, k)`
// is the node at (i, j, k) given the row offset i stride_i + j stride_j.
template <typename Real, int W, typename NodeAt>
inline void ScatterStencil(const StencilLanes<Real, W>& stencil, int l,
                           const NodeMomentum<Real>& values, std::size_t stride_i,
                           std::size_t stride_j, NodeAt&& node_at) {
  const auto& w = stencil.w;
  // Weights along k and the values' steps along k, broadcast once per particle.
  const Vector4<Real> w_k[3] = {Vector4<Real>::Constant(w[2][0][l]),
                                Vector4<Real>::Constant(w[2][1][l]),
                                Vector4<Real>::Constant(w[2][2][l])};
  const Vector4<Real> step_k[3] = {Real(0) * values.step[2], values.step[2],
                                   Real(2) * values.step[2]};
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) {
    const Vector4<Real> value_i = values.at_first_node + Real(i) * values.step[0];
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const Vector4<Real> value_ij = value_i + Real(j) * values.step[1];
      const Vector4<Real> weight_ij = Vector4<Real>::Constant(w[0][i][l] * w[1][j][l]);
      const std::size_t row = i * stride_i + j * stride_j;
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) {
        node_at(row, k) += weight_ij.cwiseProduct(w_k[k]).cwiseProduct(value_ij + step_k[k]);
      }
    }
  }
}

constexpr int kLanes = 8;  // particles whose stencils are computed together (SIMD)

// Waits until another thread has stored `stamp` in `flag` (release), then sees what it wrote.
inline void WaitForStamp(const std::uint32_t* flag, std::uint32_t stamp) {
  int spins = 0;
  while (__atomic_load_n(flag, __ATOMIC_ACQUIRE) != stamp) {
    if (++spins < 4096) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    } else {
      std::this_thread::yield();  // the thread we wait for may have been descheduled
    }
  }
}

inline void MarkDone(std::uint32_t* flag, std::uint32_t stamp) {
  __atomic_store_n(flag, stamp, __ATOMIC_RELEASE);
}

}  // namespace

template <typename Real>
void Solver<Real>::ScatterToGrid(const SubstepContext& context) {
  const Particles<Real>& p = particles_;
  Grid& grid = *grid_;
  const ParticleBlocks& blocks = workspace_->blocks;
  const Real inv_dx = Real(1.0 / context.dx_m);
  // Raw pointers: the hot loop reads no vector headers.
  const NodeMomentum<Real>* const node_momentum = workspace_->node_momentum.data();
  const Real* const position[3] = {p.position[0].data(), p.position[1].data(), p.position[2].data()};
  const std::int8_t* const blade_side = p.blade_side.data();
  const std::uint32_t* const order = blocks.order.data();
  const std::uint32_t* const block_start = blocks.block_start.data();
  GridNode<Real>* const nodes = grid.node.data();
  const std::int32_t* const split_slot = grid.split_slot.data();
  GridNode<Real>* const layer[2] = {grid.layer[0].data(), grid.layer[1].data()};
  const std::size_t stride_i = grid.stride_i();
  const std::size_t stride_j = grid.stride_j();
  const Eigen::Vector3i origin = grid.origin;
  const Eigen::Vector3i dims = grid.dims;

  Workspace& work = *workspace_;
  const std::size_t chunks = ChunkCount(active_count_);
  const std::uint32_t* const by_colour = blocks.by_colour.data();
  const std::int64_t items = static_cast<std::int64_t>(chunks + blocks.by_colour.size());
  const std::uint32_t stamp = work.stamp;
  std::uint32_t* const chunk_done = work.chunk_done.data();
  std::uint32_t* const block_done = work.block_done.data();
  const Eigen::Vector3i counts = blocks.counts;
  // Waits for the stress chunks holding the block's particles (the sort is stable, so its first
  // and last entries are its lowest and highest particle index) and for its lower-colour
  // neighbours (the blocks whose nodes overlap its own).
  auto wait_for_inputs = [&](std::uint32_t block) {
    const std::uint32_t first_chunk = order[block_start[block]] / kChunk;
    const std::uint32_t last_chunk = order[block_start[block + 1] - 1] / kChunk;
    for (std::uint32_t c = first_chunk; c <= last_chunk; ++c) WaitForStamp(chunk_done + c, stamp);
    const int bz = static_cast<int>(block % counts.z());
    const int by = static_cast<int>((block / counts.z()) % counts.y());
    const int bx = static_cast<int>(block / (static_cast<std::size_t>(counts.y()) * counts.z()));
    const int colour = ParticleBlocks::Colour(bx, by, bz);
    for (int nx = std::max(0, bx - 1); nx <= std::min(counts.x() - 1, bx + 1); ++nx) {
      for (int ny = std::max(0, by - 1); ny <= std::min(counts.y() - 1, by + 1); ++ny) {
        for (int nz = std::max(0, bz - 1); nz <= std::min(counts.z() - 1, bz + 1); ++nz) {
          if (ParticleBlocks::Colour(nx, ny, nz) >= colour) continue;
          const std::size_t neighbour = blocks.Index(nx, ny, nz);
          if (block_start[neighbour] == block_start[neighbour + 1]) continue;  // empty: never runs
          WaitForStamp(block_done + neighbour, stamp);
        }
      }
    }
  };

  const int team = omp_get_num_threads();
  bool sorted = false;  // the block order is complete (the sort ends without a barrier)
  for (;;) {
    const std::int64_t item = work.next_item.fetch_add(1, std::memory_order_relaxed);
    if (item >= items) break;
    if (item < static_cast<std::int64_t>(chunks)) {
      const std::size_t begin = static_cast<std::size_t>(item) * kChunk;
      work.elastic_energy_of_chunk[item] =
          ComputeAffineMomentum(context, begin, std::min(active_count_, begin + kChunk));
      MarkDone(chunk_done + item, stamp);
      continue;
    }
    if (!sorted) {
      for (int spins = 0; work.sorted_threads.load(std::memory_order_acquire) < team; ++spins) {
        if (spins > 4096) std::this_thread::yield();
      }
      sorted = true;
    }
    const std::uint32_t block = by_colour[item - chunks];
    wait_for_inputs(block);
    {
      // Only particles in blocks that reach a split node look up the per-side layers.
      const bool near_split = context.split_on && blocks.near_split[block];
      const std::uint32_t end = block_start[block + 1];
      for (std::uint32_t s0 = block_start[block]; s0 < end; s0 += kLanes) {
        // The stencils of up to 8 particles at once (the last one repeated to fill the lanes).
        std::uint32_t q[kLanes];
        Real lane_position[3][kLanes];
        for (int l = 0; l < kLanes; ++l) {
          q[l] = order[std::min(s0 + l, end - 1)];
          for (int axis = 0; axis < 3; ++axis) lane_position[axis][l] = position[axis][q[l]];
        }
        StencilLanes<Real, kLanes> stencil;
        StencilBatch<Real, kLanes>(lane_position, inv_dx, origin, dims, &stencil);
        const int lanes = static_cast<int>(std::min<std::uint32_t>(kLanes, end - s0));
        for (int l = 0; l < lanes; ++l) {
          const NodeMomentum<Real> values = node_momentum[q[l]];  // a copy: node stores cannot alias it
          const std::size_t first = stencil.first_node[l];
          if (!near_split) {
            GridNode<Real>* const corner = nodes + first;
            ScatterStencil(stencil, l, values, stride_i, stride_j,
                           [corner](std::size_t row, int k) -> GridNode<Real>& { return corner[row + k]; });
          } else {
            GridNode<Real>* const own_layer = layer[blade_side[q[l]] > 0 ? 1 : 0];
            ScatterStencil(stencil, l, values, stride_i, stride_j,
                           [&](std::size_t row, int k) -> GridNode<Real>& {
                             const std::size_t node = first + row + k;
                             const std::int32_t slot = split_slot[node];
                             return slot >= 0 ? own_layer[slot] : nodes[node];
                           });
          }
        }
      }
    }
    MarkDone(block_done + block, stamp);
  }
#pragma omp barrier
}

template void Solver<float>::ScatterToGrid(const SubstepContext&);
template void Solver<double>::ScatterToGrid(const SubstepContext&);

}  // namespace culinarycut::mpm
