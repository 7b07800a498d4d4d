// Corotated elasticity with damage, and J2 plasticity by radial return (paper supplement, "P2G").
// Small fixed-size math on Eigen 3x3 matrices, inlined into the transfer loops.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace culinarycut::mpm {

template <typename Real>
using Matrix3 = Eigen::Matrix<Real, 3, 3>;

// Rotation R of the polar decomposition F = R S for det F > 0, by scaled Newton iteration
// X <- (g X + X^-T / g) / 2 with the Frobenius scaling g = sqrt(|X^-1| / |X|) (Higham), which
// converges quadratically; it stops once an iteration changes X by less than round-off allows.
template <typename Real>
Matrix3<Real> PolarRotation(const Matrix3<Real>& F) {
  constexpr int kMaxIterations = 12;
  const Real tolerance = std::numeric_limits<Real>::epsilon() * Real(64);
  Matrix3<Real> X = F;
  for (int i = 0; i < kMaxIterations; ++i) {
    const Matrix3<Real> inverse = X.inverse();
    const Real g = std::sqrt(inverse.norm() / X.norm());
    const Matrix3<Real> next = Real(0.5) * (g * X + inverse.transpose() / g);
    const Real change = (next - X).squaredNorm();
    X = next;
    if (change < tolerance * tolerance) break;
  }
  return X;
}

template <typename Real>
struct Lame {
  Real mu;      // Pa
  Real lambda;  // Pa
};

// Lame parameters after damage D: the paper's damage "linearly reduces the effective moduli", here
// mu always and lambda only for volume growth; a compressed particle (J < 1) keeps lambda whatever
// its damage, after the volumetric-deviatoric split of Amor, Marigo & Maurini (2009), so that food
// under the edge is not crushed to the J clamp once it is damaged. Unlike that split it keeps
// lambda, not the bulk modulus K = lambda + 2 mu / 3: the corotated 2 mu (F - R) F^T also resists
// volume change and softens with mu, so a broken particle keeps lambda / K of its stiffness against
// small compression (0.44 at nu = 0.17, the apple; 0.69 at 0.3; 0.81 at 0.37, the cucumber; 0.93
// at 0.45) and no tension or shear (tests/sim/mpm/test_constitutive.cc).
template <typename Real>
Lame<Real> DamagedLame(Real mu_pa, Real lambda_pa, Real damage, Real J) {
  const Real scale = Real(1) - damage;
  return {mu_pa * scale, J < Real(1) ? lambda_pa : lambda_pa * scale};
}

// Kirchhoff stress tau = P F^T of corotated elasticity, P = 2 mu (F - R) + lambda (J - 1) J F^-T
// (paper eq. corot_simple), so tau = 2 mu (F - R) F^T + lambda (J - 1) J I.
template <typename Real>
Matrix3<Real> CorotatedKirchhoffStress(const Matrix3<Real>& F, const Matrix3<Real>& R, Real J,
                                       const Lame<Real>& lame) {
  return Real(2) * lame.mu * (F - R) * F.transpose() +
         Matrix3<Real>::Identity() * (lame.lambda * (J - Real(1)) * J);
}

// Elastic energy density psi = mu |F - R|^2 + lambda / 2 (J - 1)^2, J/m^3.
template <typename Real>
Real CorotatedEnergyDensity(const Matrix3<Real>& F, const Matrix3<Real>& R, Real J,
                            const Lame<Real>& lame) {
  return lame.mu * (F - R).squaredNorm() + Real(0.5) * lame.lambda * (J - Real(1)) * (J - Real(1));
}

// Below this fraction of the yield strain, |dev(E_green)| proves that a particle has not yielded:
// |dev(E_green)| >= 0.7 |dev(log S)| while the deviatoric log strain stays below about 0.3, and
// >= 0.54 of it at 50 % compression (the worst case the J clamp allows).
template <typename Real>
Real YieldTestFraction(Real yield_strain) {
  return yield_strain <= Real(0.3) ? Real(0.7) : Real(0.5);
}

// J2 (von Mises) plasticity by radial return on the Hencky strain of the stretch S = R^T F:
// the deviatoric log strain is projected back to the yield surface |dev eps| = sigma_y / (2 mu)
// * sqrt(2/3) (scaled by `return_fraction` for viscoplastic relaxation). Returns the increment of
// equivalent plastic strain; F is updated in place. A cheap Green-strain test skips the
// eigen-decomposition for particles far from yielding.
template <typename Real>
Real ReturnToYieldSurface(Matrix3<Real>* F, const Matrix3<Real>& R, Real yield_stress_pa,
                          Real mu_pa, Real return_fraction) {
  const Real yield_strain = std::sqrt(Real(2) / Real(3)) * yield_stress_pa / (Real(2) * mu_pa);
  // Cheap test first (see YieldTestFraction).
  const Matrix3<Real> green = Real(0.5) * (F->transpose() * (*F) - Matrix3<Real>::Identity());
  const Matrix3<Real> green_dev = green - Matrix3<Real>::Identity() * (green.trace() / Real(3));
  if (green_dev.norm() < YieldTestFraction(yield_strain) * yield_strain) return Real(0);

  Matrix3<Real> S = R.transpose() * (*F);
  S = Real(0.5) * (S + S.transpose());
  Eigen::SelfAdjointEigenSolver<Matrix3<Real>> eigen;
  eigen.computeDirect(S);
  Eigen::Matrix<Real, 3, 1> log_stretch = eigen.eigenvalues().cwiseMax(Real(1e-6)).array().log();
  const Real volumetric = log_stretch.sum() / Real(3);
  Eigen::Matrix<Real, 3, 1> deviatoric = log_stretch.array() - volumetric;
  const Real norm = deviatoric.norm();
  if (norm <= yield_strain) return Real(0);
  const Real excess = (norm - yield_strain) * return_fraction;
  deviatoric *= (norm - excess) / norm;
  const Eigen::Matrix<Real, 3, 1> stretch = (deviatoric.array() + volumetric).exp();
  *F = R * eigen.eigenvectors() * stretch.asDiagonal() * eigen.eigenvectors().transpose();
  return std::sqrt(Real(2) / Real(3)) * excess;
}

}  // namespace culinarycut::mpm
