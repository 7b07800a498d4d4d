// Polar rotations of a batch of deformation gradients at once, written lane by lane so that the
// compiler vectorises it (one SIMD lane per particle): the hot spot of the stress computation.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace culinarycut::mpm {

// R of F = R S for `W` matrices F[k][lane] (row-major k = 3 row + column), det F > 0. Scaled
// Newton (Higham) with the Frobenius scaling, branch-free within an iteration. The batch stops once
// no lane's iterate changed by more than PolarRotation's tolerance (constitutive.h): Newton converges
// quadratically, so food near rest (|F - R| ~ 1e-3) takes 2 iterations, where a fixed count must
// cover the largest stretch the J clamp allows (5). The stop depends only on the batch's own
// matrices, so the result is the same on any thread count.
template <typename Real, int W>
void PolarRotationBatch(const Real (&F)[9][W], Real (&R)[9][W]) {
  constexpr int kMaxIterations = 12;  // PolarRotation's bound; the J clamp's stretches converge in 5
  constexpr Real kTolerance = std::numeric_limits<Real>::epsilon() * Real(64);
  Real X[9][W];
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < W; ++l) X[k][l] = F[k][l];
  }
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    Real cof[9][W];  // cofactor matrix: inverse transpose times det
    Real det[W], scale_x[W], scale_inv[W], change[W];
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
      change[l] = 0;
    }
    for (int k = 0; k < 9; ++k) {
      for (int l = 0; l < W; ++l) {
        const Real next = scale_x[l] * X[k][l] + scale_inv[l] * cof[k][l];
        change[l] += (next - X[k][l]) * (next - X[k][l]);
        X[k][l] = next;
      }
    }
    Real largest_change = 0;
    for (int l = 0; l < W; ++l) largest_change = std::max(largest_change, change[l]);
    if (largest_change < kTolerance * kTolerance) break;
  }
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < W; ++l) R[k][l] = X[k][l];
  }
}

}  // namespace culinarycut::mpm
