// The damaged corotated stress of a batch of particles at once, lane by lane so that the compiler
// vectorises it (one SIMD lane per particle). Same formulas as constitutive.h.
#pragma once

#include <cmath>

namespace culinarycut::mpm {

// Squared norm of the deviatoric Green strain dev(E), E = (F^T F - I) / 2, per lane: a cheap test
// for particles that may have yielded.
template <typename Real, int W>
void DeviatoricGreenStrainSquared(const Real (&F)[9][W], Real (&out)[W]) {
  for (int l = 0; l < W; ++l) {
    Real E[9];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        E[3 * a + b] = Real(0.5) * (F[a][l] * F[b][l] + F[3 + a][l] * F[3 + b][l] +
                                    F[6 + a][l] * F[6 + b][l] - (a == b ? Real(1) : Real(0)));
      }
    }
    const Real mean = (E[0] + E[4] + E[8]) / Real(3);
    E[0] -= mean;
    E[4] -= mean;
    E[8] -= mean;
    Real sum = 0;
    for (int k = 0; k < 9; ++k) sum += E[k] * E[k];
    out[l] = sum;
  }
}

// affine = volume_scale * tau + m C with tau = 2 mu (F - R) F^T + lambda (J - 1) J I, and the
// elastic energy volume * (mu |F - R|^2 + lambda / 2 (J - 1)^2), per lane. lambda is
// `lambda_compressed` where J < 1 and `lambda_stretched` elsewhere (damage keeps compression).
template <typename Real, int W>
void CorotatedAffineBatch(const Real (&F)[9][W], const Real (&R)[9][W], const Real (&C)[9][W],
                          const Real (&mu)[W], const Real (&lambda_stretched)[W],
                          const Real (&lambda_compressed)[W],
                          const Real (&volume_scale)[W], const Real (&mass)[W],
                          const Real (&volume)[W], Real (&affine)[9][W], Real (&energy)[W]) {
  for (int l = 0; l < W; ++l) {
    Real D[9];
    Real norm = 0;
    for (int k = 0; k < 9; ++k) {
      D[k] = F[k][l] - R[k][l];
      norm += D[k] * D[k];
    }
    const Real J = F[0][l] * (F[4][l] * F[8][l] - F[5][l] * F[7][l]) -
                   F[1][l] * (F[3][l] * F[8][l] - F[5][l] * F[6][l]) +
                   F[2][l] * (F[3][l] * F[7][l] - F[4][l] * F[6][l]);
    const Real lambda = J < Real(1) ? lambda_compressed[l] : lambda_stretched[l];
    const Real pressure = lambda * (J - Real(1)) * J;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        const Real DFt = D[3 * a] * F[3 * b][l] + D[3 * a + 1] * F[3 * b + 1][l] +
                         D[3 * a + 2] * F[3 * b + 2][l];
        const Real tau = Real(2) * mu[l] * DFt + (a == b ? pressure : Real(0));
        affine[3 * a + b][l] = volume_scale[l] * tau + mass[l] * C[3 * a + b][l];
      }
    }
    energy[l] = volume[l] * (mu[l] * norm + Real(0.5) * lambda * (J - Real(1)) * (J - Real(1)));
  }
}

}  // namespace culinarycut::mpm
