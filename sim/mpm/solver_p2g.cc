// P2G, part 2: each particle's mass and APIC momentum to its 27 grid nodes, block colour by block
// colour (blocks of one colour never share a node: no locks, and the same sums on any threads).
#include <algorithm>

#include "sim/mpm/solver_internals.h"
#include "sim/mpm/transfer_stencil.h"

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

  for (int colour = 0; colour < 8; ++colour) {
    const std::vector<std::uint32_t>& colour_blocks = blocks.of_colour[colour];
#pragma omp parallel for num_threads(config_.threads) schedule(dynamic, 1)
    for (std::int64_t b = 0; b < static_cast<std::int64_t>(colour_blocks.size()); ++b) {
      const std::uint32_t block = colour_blocks[b];
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
  }
}

template void Solver<float>::ScatterToGrid(const SubstepContext&);
template void Solver<double>::ScatterToGrid(const SubstepContext&);

}  // namespace culinarycut::mpm
