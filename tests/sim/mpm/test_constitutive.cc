// Damaged corotated elasticity (constitutive.h, stress_batch.h): damage D scales shear and volume
// growth by 1 - D but keeps the volumetric term lambda (J - 1) J under compression, so broken
// food still resists being squeezed and carries no tension or shear.
#include <cmath>
#include <utility>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/physics/constitutive.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/kernels/polar_batch.h"
#include "sim/mpm/kernels/stress_batch.h"

namespace culinarycut::mpm {
namespace {

using Matrix = Matrix3<double>;

// F = R S with a known rotation R and symmetric stretch S (principal stretches along rotated axes).
Matrix3<float> KnownDeformation(const Eigen::Vector3d& axis, double angle_rad, const Eigen::Vector3d& stretches,
                                const Eigen::Matrix3d& principal_axes, Matrix3<double>* rotation) {
  *rotation = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  const Eigen::Matrix3d S = principal_axes * stretches.asDiagonal() * principal_axes.transpose();
  return (*rotation * S).cast<float>();
}

TEST_CASE("the batched polar rotation finds the known rotation, near rest and at large stretches",
          "[mpm][constitutive]") {
  // One batch mixes a particle at rest with ones at the J clamp's bounds and beyond, sheared along
  // tilted axes: the batch iterates until its slowest lane has converged, and every lane must come
  // out at the rotation F was built from.
  const Eigen::Matrix3d tilted = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const struct {
    Eigen::Vector3d axis;
    double angle_rad;
    Eigen::Vector3d stretches;
    Eigen::Matrix3d principal_axes;
  } cases[8] = {
      {{0, 0, 1}, 0.0, {1, 1, 1}, Eigen::Matrix3d::Identity()},
      {{0, 0, 1}, 0.3, {1.001, 0.999, 1.0005}, tilted},
      {{1, 1, 0}, 1.2, {1.1, 0.95, 1.0}, tilted},
      {{1, 0, 0}, 2.5, {1.6, 1.0, 1.0}, Eigen::Matrix3d::Identity()},
      {{0, 1, 1}, -0.8, {0.6, 1.0, 1.0}, tilted},
      {{3, -1, 2}, 3.0, {2.5, 0.8, 0.5}, tilted},
      {{1, 1, 1}, 0.05, {4.0, 0.5, 0.5}, tilted},
      {{0, 1, 0}, -2.0, {0.3, 1.2, 2.0}, Eigen::Matrix3d::Identity()},
  };
  float F[9][8], R[9][8];
  Matrix3<double> expected[8];
  for (int l = 0; l < 8; ++l) {
    const Matrix3<float> deformation =
        KnownDeformation(cases[l].axis, cases[l].angle_rad, cases[l].stretches, cases[l].principal_axes, &expected[l]);
    for (int k = 0; k < 9; ++k) F[k][l] = deformation(k / 3, k % 3);
  }
  PolarRotationBatch<float, 8>(F, R);
  for (int l = 0; l < 8; ++l) {
    Matrix3<double> found;
    for (int k = 0; k < 9; ++k) found(k / 3, k % 3) = R[k][l];
    INFO("lane " << l << ": |R - R_known| = " << (found - expected[l]).norm());
    CHECK((found - expected[l]).norm() < 2e-6);
    CHECK((found.transpose() * found - Matrix3<double>::Identity()).norm() < 2e-6);
  }
  // A batch of particles at rest stops after one iteration with the rotation itself.
  float rest[9][8], rest_R[9][8];
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < 8; ++l) rest[k][l] = k % 4 == 0 ? 1.0f : 0.0f;
  }
  PolarRotationBatch<float, 8>(rest, rest_R);
  for (int k = 0; k < 9; ++k) {
    for (int l = 0; l < 8; ++l) CHECK(rest_R[k][l] == rest[k][l]);
  }
}

// Kirchhoff stress (Pa) of a particle with deformation F and damage D, on the scalar path.
Matrix Stress(const Material& material, const Matrix& F, double damage) {
  const double J = F.determinant();
  const Lame<double> lame = DamagedLame(material.shear_modulus_pa(), material.lame_lambda_pa(), damage, J);
  return CorotatedKirchhoffStress<double>(F, PolarRotation(F), J, lame);
}

// The same on the batched path, with the Lame parameters as the solver's stress pass gives them
// (solver_stress.cc: mu and lambda times 1 - D, lambda undamaged where J < 1); mass 0 and a unit
// volume scale make the affine matrix the stress itself.
Matrix BatchStress(const Material& material, const Matrix& F, double damage) {
  double F_lanes[9][1], R_lanes[9][1], C[9][1] = {}, affine[9][1];
  const Matrix R = PolarRotation(F);
  for (int k = 0; k < 9; ++k) {
    F_lanes[k][0] = F(k / 3, k % 3);
    R_lanes[k][0] = R(k / 3, k % 3);
  }
  const double mu[1] = {material.shear_modulus_pa() * (1.0 - damage)};
  const double lambda_stretched[1] = {material.lame_lambda_pa() * (1.0 - damage)};
  const double lambda_compressed[1] = {material.lame_lambda_pa()};
  const double volume_scale[1] = {1.0}, mass[1] = {0.0}, volume[1] = {1.0};
  double energy[1];
  CorotatedAffineBatch<double, 1>(F_lanes, R_lanes, C, mu, lambda_stretched, lambda_compressed,
                                  volume_scale, mass, volume, affine, energy);
  Matrix tau;
  for (int k = 0; k < 9; ++k) tau(k / 3, k % 3) = affine[k][0];
  return tau;
}

double Pressure(const Matrix& tau) { return -tau.trace() / 3.0; }  // Kirchhoff pressure, Pa
Matrix Deviator(const Matrix& tau) { return tau - Matrix::Identity() * (tau.trace() / 3.0); }

TEST_CASE("a fully damaged particle keeps its volumetric pressure under compression", "[mpm][constitutive]") {
  const Material material = testing::SoftMaterial(1e6, 0.3);
  const double lambda_pa = material.lame_lambda_pa();
  const double mu_pa = material.shear_modulus_pa();
  // 2 % squeezed along z and 1 % along x: a compression with shear in it, J = 0.970.
  const Matrix F = Eigen::Vector3d(0.99, 1.0, 0.98).asDiagonal().toDenseMatrix();
  const double J = F.determinant();
  REQUIRE(J < 1.0);
  const Matrix intact = Stress(material, F, 0.0);
  for (const double damage : {0.5, 0.9, 1.0}) {
    INFO("D = " << damage);
    const Matrix damaged = Stress(material, F, damage);
    // The volumetric term is the undamaged one's, whatever D: lambda (J - 1) J, Pa.
    const double volumetric_pa = -lambda_pa * (J - 1.0) * J;
    CHECK(Pressure(damaged) == Approx(volumetric_pa + (1.0 - damage) * (Pressure(intact) - volumetric_pa)));
    CHECK(Pressure(damaged) > 0.0);
    // The shear part is softened by 1 - D.
    CHECK((Deviator(damaged) - (1.0 - damage) * Deviator(intact)).norm() < 1e-9 * Deviator(intact).norm());
    CHECK((BatchStress(material, F, damage) - damaged).norm() < 1e-9 * damaged.norm());
  }
  // Broken through (D = 1): a pure pressure, lambda / (lambda + 2 mu / 3) = 0.69 of the intact
  // one at nu = 0.3 (the corotated 2 mu (F - R) F^T term also resists volume change; it goes).
  const Matrix broken = Stress(material, F, 1.0);
  CHECK(Deviator(broken).norm() < 1e-9 * broken.norm());
  CHECK(Pressure(broken) / Pressure(intact) == Approx(lambda_pa / (lambda_pa + 2.0 * mu_pa / 3.0)).epsilon(0.02));
}

TEST_CASE("a fully damaged particle carries no tension and no shear", "[mpm][constitutive]") {
  const Material material = testing::SoftMaterial(1e6, 0.3);
  const Matrix stretched = Eigen::Vector3d(1.0, 1.0, 1.02).asDiagonal().toDenseMatrix();  // J = 1.02
  Matrix sheared = Matrix::Identity();
  sheared(0, 1) = 0.05;  // simple shear, J = 1
  for (const Matrix& F : {stretched, sheared}) {
    const Matrix intact = Stress(material, F, 0.0);
    REQUIRE(intact.norm() > 1e3);  // Pa: the intact particle does resist
    CHECK((Stress(material, F, 0.5) - 0.5 * intact).norm() < 1e-9 * intact.norm());
    CHECK(Stress(material, F, 1.0).norm() == 0.0);
    CHECK(BatchStress(material, F, 1.0).norm() == 0.0);
    CHECK((BatchStress(material, F, 0.5) - 0.5 * intact).norm() < 1e-9 * intact.norm());
  }
}

// The lowest J and the J clamps of a fully damaged 4 x 4 x 2 cm block of E 50 kPa left on the
// board under gravity for 50 ms.
std::pair<double, std::int64_t> DamagedBlockUnderGravity(double poisson) {
  SolverConfig config;
  Solver<float> solver(config, {testing::SoftMaterial(5e4, poisson)});
  testing::AddBlock<float>({0.48, -0.02, 0.02}, {0.52, 0.02, 0.04}, config.dx_m, 2, 1000.0, &solver.particles());
  testing::AddBoardAndTable(&solver);
  for (auto& damage : solver.particles().damage) damage = 1.0f;
  const double dt_s = solver.StableTimestep();
  double j_min = 1.0;
  std::int64_t j_clamps = 0;
  for (double t_s = 0.0; t_s < 0.05; t_s += dt_s) {
    const SubstepDiagnostics d = solver.Substep(dt_s);
    j_min = std::min(j_min, d.j_min);
    j_clamps += d.j_clamps;
  }
  return {j_min, j_clamps};
}

TEST_CASE("a fully damaged block on the board is not crushed by its own weight", "[mpm][constitutive]") {
  // Broken food has no shear stiffness, so it slumps like a liquid, but it keeps lambda against
  // compression: J stays near 1 - rho g h / lambda = 0.993 (static) instead of falling to j_min.
  const auto [j_min, j_clamps] = DamagedBlockUnderGravity(0.3);
  // With nu = 0 (lambda = 0) the broken block has nothing left against compression: the check
  // above tells the two apart.
  const auto [j_min_no_lambda, j_clamps_no_lambda] = DamagedBlockUnderGravity(0.0);
  INFO("nu 0.3: J min " << j_min << ", clamps " << j_clamps << "; nu 0: J min " << j_min_no_lambda
                        << ", clamps " << j_clamps_no_lambda);
  CHECK(j_clamps == 0);
  CHECK(j_min > 0.9);
  CHECK(j_min_no_lambda < 0.9);
}

TEST_CASE("a fully broken block sheared hard keeps only its volume change, finite", "[mpm][constitutive]") {
  // Broken food's stress depends on J alone, so its F is kept as J^(1/3) I. Sheared at 50 / s for
  // 50 ms (F_xz would reach 2.5 if it kept the shape), its F must stay isotropic and finite, with the
  // same J as the shear's volume change gives: none, up to the flow's own compression.
  SolverConfig config;
  Solver<float> solver(config, {testing::SoftMaterial(5e4, 0.3)});
  testing::AddBlock<float>({0.48, -0.02, 0.02}, {0.52, 0.02, 0.04}, config.dx_m, 2, 1000.0, &solver.particles());
  Particles<float>& p = solver.particles();
  for (std::size_t q = 0; q < p.size(); ++q) {
    p.damage[q] = 1.0f;
    p.velocity[0][q] = 50.0f * (p.position[2][q] - 0.03f);  // m/s: v_x = 50 (z - 0.03 m)
  }
  const double dt_s = solver.StableTimestep();  // the wave speed bounds it: the flow is at most 0.5 m/s
  for (double t_s = 0.0; t_s < 0.05; t_s += dt_s) solver.Substep(dt_s);
  double largest_shear = 0.0, j_low = 10.0, j_high = 0.0;
  bool finite = true;
  for (std::size_t q = 0; q < p.size(); ++q) {
    Matrix3<double> F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
    finite = finite && F.allFinite();
    const double stretch = std::cbrt(F.determinant());
    largest_shear = std::max(largest_shear, (F - stretch * Matrix3<double>::Identity()).norm());
    j_low = std::min(j_low, F.determinant());
    j_high = std::max(j_high, F.determinant());
  }
  INFO("largest |F - J^(1/3) I| " << largest_shear << ", J in [" << j_low << ", " << j_high << "]");
  CHECK(finite);
  CHECK(largest_shear < 1e-6);
  CHECK(j_low > config.j_min);
  CHECK(j_high < config.j_max);
}

}  // namespace
}  // namespace culinarycut::mpm
