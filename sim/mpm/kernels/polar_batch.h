// Polar rotations of a batch of deformation gradients at once, written lane by lane so that the
// compiler vectorises it (one SIMD lane per particle): the hot spot of the stress computation.
#pragma once

#include <cmath>

namespace culinarycut::mpm {

// R of F = R S for `W` matrices F[k][lane] (row-major k = 3 row + column), det F > 0. Scaled
// Newton (Higham) with the Frobenius scaling, a fixed 5 iterations: branch-free, and past float
// round-off for the stretches the J clamp allows.
template <typename Real, int W>
void PolarRotationBatch(const Real (&F)[9][W], Real (&R)[9][W]) {
  constexpr int kIterations = 5;
  Real X[9][W];
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < W; ++l) X[k][l] = F[k][l];
  }
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    Real cof[9][W];  // cofactor matrix: inverse transpose times det
    Real det[W], scale_x[W], scale_inv[W];
    for (int l = 0; l < W; ++l) {
      cof[0][l] = X[4][l] * X[8][l] - X[5][l] * X[7][l];
      cof[1][l] = X[5][l] * X[6][l] - X[3][l] * X[8][l];
      cof[2][l] = X[3][l] * X[7][l] - X[4][l] * X[6][l];
      cof[3][l] = X[2][l] * X[7][l] - X[1][l] * X[8][l];
      cof[4][l] = X[0][l] * X[8][l] - X[2][l] * X[6][l];
      cof[5][l] = X[1][l] * X[6][l] - X[0][l] * X[7][l];
      cof[6][l] = X[1][l] * X[5][l] - X[2][l] * X[4][l];
      cof[7][l] = X[2][l] * X[3][l] - X[0][l] * X[5][l];
      cof[8][l] = X[0][l] * X[4][l] - X[1][l] * X[3][l];
      det[l] = X[0][l] * cof[0][l] + X[1][l] * cof[1][l] + X[2][l] * cof[2][l];
    }
    for (int l = 0; l < W; ++l) {
      Real norm_x = 0, norm_cof = 0;
      for (int k = 0; k < 9; ++k) {
        norm_x += X[k][l] * X[k][l];
        norm_cof += cof[k][l] * cof[k][l];
      }
      // |X^-T| = |cof| / |det|; g = sqrt(|X^-1| / |X|) = (|cof|^2 / (|X|^2 det^2))^(1/4): two
      // divisions and two square roots per iteration (they dominate its cost).
      const Real g = std::sqrt(std::sqrt(norm_cof / (norm_x * det[l] * det[l])));
      scale_x[l] = Real(0.5) * g;
      scale_inv[l] = Real(0.5) / (det[l] * g);
    }
    for (int k = 0; k < 9; ++k) {
      for (int l = 0; l < W; ++l) X[k][l] = scale_x[l] * X[k][l] + scale_inv[l] * cof[k][l];
    }
  }
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < W; ++l) R[k][l] = X[k][l];
  }
}

}  // namespace culinarycut::mpm
