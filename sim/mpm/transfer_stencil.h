// Which grid nodes a particle talks to, and with what weights: quadratic B-splines (MLS-MPM).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/particles.h"

namespace culinarycut::mpm {

// floor() as an int without a libm call (SSE2 has no rounding instruction; floorf is a hot spot).
template <typename Real>
inline int FloorToInt(Real x) {
  const int truncated = static_cast<int>(x);
  return truncated - (x < Real(truncated) ? 1 : 0);
}

// Quadratic B-spline weights of the 3 nodes base, base+1, base+2 along one axis; `fx` is the
// particle's position relative to node `base`, in cells (in [0.5, 1.5)).
template <typename Real>
inline void QuadraticWeights(Real fx, Real w[3]) {
  w[0] = Real(0.5) * (Real(1.5) - fx) * (Real(1.5) - fx);
  w[1] = Real(0.75) - (fx - Real(1)) * (fx - Real(1));
  w[2] = Real(0.5) * (fx - Real(0.5)) * (fx - Real(0.5));
}

// The cell whose node is the first of a particle's three along one axis (global index).
template <typename Real>
inline int CellOf(Real position_m, Real inv_dx) {
  return FloorToInt(position_m * inv_dx - Real(0.5));
}

// The 3 x 3 x 3 nodes a particle transfers with: the first node (grid-local index), the
// particle's offset from it in cells (in [0.5, 1.5)) and the weights, per axis.
template <typename Real>
struct Stencil {
  int base[3];
  Real fx[3];
  Real w[3][3];
};

template <typename Real>
inline Stencil<Real> StencilOf(const Particles<Real>& p, std::size_t q, Real inv_dx,
                               const Eigen::Vector3i& grid_origin) {
  Stencil<Real> stencil;
  for (int axis = 0; axis < 3; ++axis) {
    const int cell = CellOf(p.position[axis][q], inv_dx);  // the block sort uses the same cell
    stencil.base[axis] = cell - grid_origin[axis];
    stencil.fx[axis] = p.position[axis][q] * inv_dx - Real(cell);
    QuadraticWeights(stencil.fx[axis], stencil.w[axis]);
  }
  return stencil;
}

}  // namespace culinarycut::mpm
