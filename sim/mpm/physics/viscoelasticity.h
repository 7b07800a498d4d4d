// Viscoelasticity: a Maxwell branch (a spring of shear modulus mu_1 in series with a dashpot of
// relaxation time tau) beside the hyperelastic base, which together make a standard linear solid
// (Zener): instantaneous shear modulus mu + mu_1, equilibrium modulus mu. The branch carries only
// deviatoric stress, so it adds rate to shear and none to the food's bulk response.
//
// The branch's Kirchhoff stress s evolves by the upper Maxwell law in the co-rotational (Jaumann)
// rate, ds/dt = 2 mu_1 dev(D) - s / tau (Simo & Hughes, "Computational Inelasticity", 1998, ch. 10),
// with D = sym(L) and W = skew(L) from the particle's velocity gradient L (the MLS-MPM affine field
// C). Over a substep D is constant, so the exponential integrator below is exact for it and stable at
// any dt / tau: the branch needs no time step of its own beyond its wave speed.
#pragma once

#include <cmath>

namespace culinarycut::mpm {

// Components of a symmetric 3x3 tensor, in this order.
enum SymmetricComponent { kXX = 0, kYY = 1, kZZ = 2, kXY = 3, kYZ = 4, kZX = 5 };
// The row and column of each component (its transpose is the same value).
inline constexpr int kSymmetricRow[6] = {0, 1, 2, 0, 1, 2};
inline constexpr int kSymmetricColumn[6] = {0, 1, 2, 1, 2, 0};

// How much of the branch's stress survives a substep, exp(-dt / tau), and the weight of the strain
// rate over it, (1 - exp(-dt / tau)) tau / dt (-> 1 as dt / tau -> 0). tau <= 0: no branch.
struct MaxwellStep {
  double decay = 0.0;
  double rate_weight = 0.0;
};

inline MaxwellStep MaxwellStepFor(double dt_s, double relaxation_time_s) {
  if (!(relaxation_time_s > 0.0)) return {};
  const double h = dt_s / relaxation_time_s;
  const double decay = std::exp(-h);
  // -expm1 keeps the weight exact to round-off when dt << tau.
  return {decay, h > 0.0 ? -std::expm1(-h) / h : 1.0};
}

// One substep of the Maxwell branch (the law above): s <- decay (s + dt (W s - s W)) + 2 mu_1 dt
// rate_weight dev(D). `s` holds the six components (Pa) in SymmetricComponent order; `L` is the
// velocity gradient (1/s) row-major, L[3 r + c] = d v_r / d x_c.
template <typename Real>
inline void UpdateMaxwellStress(const Real (&L)[9], Real dt_s, Real shear_modulus_pa, const MaxwellStep& step,
                                Real (&s)[6]) {
  const Real S[3][3] = {{s[kXX], s[kXY], s[kZX]}, {s[kXY], s[kYY], s[kYZ]}, {s[kZX], s[kYZ], s[kZZ]}};
  Real W[3][3], D[3][3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      W[r][c] = Real(0.5) * (L[3 * r + c] - L[3 * c + r]);
      D[r][c] = Real(0.5) * (L[3 * r + c] + L[3 * c + r]);
    }
  }
  const Real trace_third = (D[0][0] + D[1][1] + D[2][2]) / Real(3);
  for (int d = 0; d < 3; ++d) D[d][d] -= trace_third;
  // The stress rotated with the material over the substep: S + dt (W S - S W).
  auto rotated = [&](int r, int c) {
    Real spin = 0;
    for (int k = 0; k < 3; ++k) spin += W[r][k] * S[k][c] - S[r][k] * W[k][c];
    return S[r][c] + dt_s * spin;
  };
  const Real decay = Real(step.decay);
  const Real drive = Real(2) * shear_modulus_pa * dt_s * Real(step.rate_weight);
  Real next[6];
  for (int k = 0; k < 6; ++k) {
    const int r = kSymmetricRow[k], c = kSymmetricColumn[k];
    next[k] = decay * rotated(r, c) + drive * D[r][c];
  }
  for (int k = 0; k < 6; ++k) s[k] = next[k];
}

// The energy the branch's spring stores per unit volume, |s|^2 / (4 mu_1) (J/m^3), with |s| the
// Frobenius norm of the full symmetric tensor.
template <typename Real>
inline Real MaxwellEnergyDensity(const Real (&s)[6], Real shear_modulus_pa) {
  if (!(shear_modulus_pa > Real(0))) return Real(0);
  const Real norm_sq = s[kXX] * s[kXX] + s[kYY] * s[kYY] + s[kZZ] * s[kZZ] +
                       Real(2) * (s[kXY] * s[kXY] + s[kYZ] * s[kYZ] + s[kZX] * s[kZX]);
  return norm_sq / (Real(4) * shear_modulus_pa);
}

}  // namespace culinarycut::mpm
