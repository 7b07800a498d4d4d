// Which grid nodes a particle talks to, and with what weights: quadratic B-splines (MLS-MPM).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

namespace culinarycut::mpm {

// floor() as an int without a libm call (SSE2 has no rounding instruction; floorf is a hot spot).
template <typename Real>
inline int FloorToInt(Real x) {
  const int truncated = static_cast<int>(x);
  return truncated - (x < Real(truncated) ? 1 : 0);
}

// The cell whose node is the first of a particle's three along one axis (global index).
template <typename Real>
inline int CellOf(Real position_m, Real inv_dx) {
  return FloorToInt(position_m * inv_dx - Real(0.5));
}

// The 3 x 3 x 3 nodes W particles transfer with, one SIMD lane each: the index of the first node
// in the grid box, the particle's offset from it in cells (in [0.5, 1.5)) and the weights, per
// axis.
template <typename Real, int W>
struct StencilLanes {
  std::uint32_t first_node[W];
  Real fx[3][W];
  Real w[3][3][W];  // [axis][node 0, 1, 2][lane]
};

// The stencils of W particles at once; `position` in m, the grid box's first node at global index
// `grid_origin`, `grid_dims` nodes.
template <typename Real, int W>
void StencilBatch(const Real (&position)[3][W], Real inv_dx, const Eigen::Vector3i& grid_origin,
                  const Eigen::Vector3i& grid_dims, StencilLanes<Real, W>* out) {
  int base[3][W];
  for (int axis = 0; axis < 3; ++axis) {
    for (int l = 0; l < W; ++l) {
      const Real x = position[axis][l];
      const int cell = CellOf(x, inv_dx);  // the block sort uses the same cell
      base[axis][l] = cell - grid_origin[axis];
      const Real fx = x * inv_dx - Real(cell);
      out->fx[axis][l] = fx;
      // Quadratic B-spline weights of the nodes cell, cell + 1, cell + 2.
      out->w[axis][0][l] = Real(0.5) * (Real(1.5) - fx) * (Real(1.5) - fx);
      out->w[axis][1][l] = Real(0.75) - (fx - Real(1)) * (fx - Real(1));
      out->w[axis][2][l] = Real(0.5) * (fx - Real(0.5)) * (fx - Real(0.5));
    }
  }
  // A separate loop: SSE2 has no 32-bit integer multiply, which would keep the one above scalar.
  for (int l = 0; l < W; ++l) {
    out->first_node[l] = static_cast<std::uint32_t>(
        (static_cast<std::size_t>(base[0][l]) * grid_dims.y() + base[1][l]) * grid_dims.z() +
        base[2][l]);
  }
}

}  // namespace culinarycut::mpm
