// What one particle adds to each of its 27 grid nodes in P2G (APIC): momentum m v + A (x_n - x_p)
// and mass m, with x_n - x_p = (n - fx) dx for the node n = (i, j, k) cells from the stencil's
// first node. As (momentum, mass) 4-vectors: at_first_node + i step[0] + j step[1] + k step[2].
// The stress pass computes it 8 particles per SIMD batch, so the scatter only adds.
#pragma once

#include <Eigen/Core>

#include "sim/mpm/kernels/transfer_stencil.h"

namespace culinarycut::mpm {

template <typename Real>
using Vector4 = Eigen::Matrix<Real, 4, 1>;

template <typename Real>
struct NodeMomentum {
  Vector4<Real> at_first_node;  // kg m/s and kg
  Vector4<Real> step[3];        // per node along each axis; mass lane 0
};

// `affine` = A (row-major, kg/s), mass (kg), velocity (m/s) and position (m) per lane.
template <typename Real, int W>
void NodeMomentumBatch(const Real (&affine)[9][W], const Real (&mass)[W],
                       const Real (&velocity)[3][W], const Real (&position)[3][W], Real inv_dx,
                       Real dx, NodeMomentum<Real>* out) {
  Real fx_m[3][W];  // the particle's offset from its stencil's first node (m)
  for (int axis = 0; axis < 3; ++axis) {
    for (int l = 0; l < W; ++l) {
      const Real x = position[axis][l];
      fx_m[axis][l] = (x * inv_dx - Real(CellOf(x, inv_dx))) * dx;
    }
  }
  Real at[3][W];  // m v - A fx dx
  for (int r = 0; r < 3; ++r) {
    for (int l = 0; l < W; ++l) {
      at[r][l] = mass[l] * velocity[r][l] -
                 (affine[3 * r][l] * fx_m[0][l] +
                  (affine[3 * r + 1][l] * fx_m[1][l] + affine[3 * r + 2][l] * fx_m[2][l]));
    }
  }
  for (int l = 0; l < W; ++l) {
    out[l].at_first_node = Vector4<Real>(at[0][l], at[1][l], at[2][l], mass[l]);
    for (int a = 0; a < 3; ++a) {
      out[l].step[a] = Vector4<Real>(affine[a][l] * dx, affine[3 + a][l] * dx,
                                     affine[6 + a][l] * dx, Real(0));
    }
  }
}

}  // namespace culinarycut::mpm
