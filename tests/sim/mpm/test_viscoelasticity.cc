// The Maxwell branch (physics/viscoelasticity.h) against the standard linear solid's closed forms:
// stress under a constant strain rate, relaxation at a held strain, and the bar wave speed at the
// instantaneous and the equilibrium modulus through the whole solver.
#include <cmath>

#include <catch2/catch.hpp>

#include "mpm_fixtures.h"
#include "sim/mpm/physics/viscoelasticity.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

using testing::AddBlock;
using testing::FirstEndVelocityReversal;
using testing::SoftMaterial;

// Pure shear at rate gamma_dot (1/s): L = D with D_xy = D_yx = gamma_dot / 2, no spin.
void PureShear(double gamma_dot_per_s, double (&L)[9]) {
  for (double& value : L) value = 0.0;
  L[1] = L[3] = 0.5 * gamma_dot_per_s;
}

// s_xy after `time_s` of the law ds/dt = 2 mu_1 D - s / tau from rest, in steps of dt_s.
double ShearStressAfter(double time_s, double dt_s, double mu_1_pa, double tau_s, double gamma_dot_per_s) {
  double L[9];
  PureShear(gamma_dot_per_s, L);
  double s[6] = {0, 0, 0, 0, 0, 0};
  const MaxwellStep step = MaxwellStepFor(dt_s, tau_s);
  const int steps = static_cast<int>(std::lround(time_s / dt_s));
  for (int i = 0; i < steps; ++i) UpdateMaxwellStress(L, dt_s, mu_1_pa, step, s);
  return s[kXY];
}

TEST_CASE("under a constant strain rate the branch follows mu_1 gamma_dot tau (1 - exp(-t / tau))",
          "[mpm][viscoelasticity]") {
  const double mu_1 = 2e5, tau = 0.05, gamma_dot = 0.4;
  for (const double t : {0.01, 0.05, 0.2}) {
    const double analytic = mu_1 * gamma_dot * tau * (1.0 - std::exp(-t / tau));
    // The integrator is exact for a rate held over the substep: any dt gives the closed form.
    for (const double dt : {1e-4, 1e-3, 1e-2}) {
      INFO("t " << t << " s, dt " << dt << " s");
      CHECK(ShearStressAfter(t, dt, mu_1, tau, gamma_dot) == Approx(analytic).epsilon(1e-9));
    }
  }
  // Far faster than it relaxes, the branch is a spring: s = mu_1 gamma (gamma = gamma_dot t).
  CHECK(ShearStressAfter(1e-4, 1e-6, mu_1, 100.0, gamma_dot) == Approx(mu_1 * gamma_dot * 1e-4).epsilon(1e-5));
}

TEST_CASE("at a held strain the branch relaxes as exp(-t / tau) and its energy with it", "[mpm][viscoelasticity]") {
  const double mu_1 = 3e5, tau = 0.02;
  double s[6] = {1e3, -4e2, -6e2, 2.5e3, 0.0, -7e2};
  const double initial_energy = MaxwellEnergyDensity(s, mu_1);
  const double L[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  const double dt = 1e-3;
  const MaxwellStep step = MaxwellStepFor(dt, tau);
  for (int i = 0; i < 40; ++i) UpdateMaxwellStress(L, dt, mu_1, step, s);  // 2 tau
  CHECK(s[kXY] == Approx(2.5e3 * std::exp(-2.0)).epsilon(1e-12));
  CHECK(s[kXX] == Approx(1e3 * std::exp(-2.0)).epsilon(1e-12));
  CHECK(MaxwellEnergyDensity(s, mu_1) == Approx(initial_energy * std::exp(-4.0)).epsilon(1e-12));
  // No branch: no step and no energy.
  CHECK(MaxwellStepFor(dt, 0.0).decay == 0.0);
  CHECK(MaxwellEnergyDensity(s, 0.0) == 0.0);
}

TEST_CASE("a rigid spin turns the branch's stress with the material and keeps its size", "[mpm][viscoelasticity]") {
  // Spin about z at omega: a stress sigma_xx = a turns into the rotated tensor; over a quarter turn in
  // small steps its norm and trace hold to first order in dt (Jaumann rate), and it ends near sigma_yy = a.
  const double omega = 10.0, dt = 1e-5;
  const double L[9] = {0, -omega, 0, omega, 0, 0, 0, 0, 0};
  double s[6] = {1e3, 0, 0, 0, 0, 0};
  const MaxwellStep step = MaxwellStepFor(dt, 1e9);  // no relaxation to speak of
  const int steps = static_cast<int>(std::lround(0.5 * M_PI / omega / dt));
  for (int i = 0; i < steps; ++i) UpdateMaxwellStress(L, dt, 1e5, step, s);
  CHECK(s[kYY] == Approx(1e3).epsilon(2e-3));
  CHECK(std::abs(s[kXX]) < 2.0);
  CHECK(std::abs(s[kXY]) < 5.0);
}

// The bar wave speed c = L / (2 t) of a free-free bar along x, from its first end-velocity reversal t.
double BarWaveSpeed(const Material& material) {
  SolverConfig config;
  config.dx_m = 0.005;
  config.gravity_m_s2.setZero();
  Solver<double> solver(config, {material});
  const double length_m = 0.4;
  AddBlock<double>({0.0, 0.0, 0.0}, {length_m, 0.01, 0.01}, config.dx_m, 2, material.density_kg_m3,
                   &solver.particles());
  auto& p = solver.particles();
  for (std::size_t q = 0; q < p.size(); ++q) p.velocity[0][q] = 0.01 * std::cos(M_PI * p.position[0][q] / length_m);
  const double crossing_s = FirstEndVelocityReversal(&solver, 0, 0.02, 4000);
  return crossing_s > 0.0 ? length_m / (2.0 * crossing_s) : 0.0;
}

TEST_CASE("a viscoelastic bar rings at the instantaneous modulus when slow to relax, the equilibrium one when fast",
          "[mpm][viscoelasticity]") {
  Material material = SoftMaterial(1e5, 0.0);
  material.maxwell_modulus_ratio = 1.0;
  const double c_equilibrium = std::sqrt(material.youngs_modulus_pa / material.density_kg_m3);
  // nu = 0: K = E / 3 and mu = E / 2; the branch doubles the shear modulus at once, so the
  // instantaneous Young's modulus is 9 K G / (3 K + G) with G = E: 1.5 E.
  const double c_instantaneous = std::sqrt(1.5) * c_equilibrium;
  SECTION("relaxation far slower than the ring (0.02 s)") {
    material.maxwell_relaxation_time_s = 1e3;
    const double c = BarWaveSpeed(material);
    INFO("measured " << c << " m/s, instantaneous " << c_instantaneous << ", equilibrium " << c_equilibrium);
    CHECK(c == Approx(c_instantaneous).epsilon(0.05));
  }
  SECTION("relaxation far faster than the ring") {
    material.maxwell_relaxation_time_s = 1e-5;
    const double c = BarWaveSpeed(material);
    INFO("measured " << c << " m/s, equilibrium " << c_equilibrium);
    CHECK(c == Approx(c_equilibrium).epsilon(0.05));
  }
  SECTION("the time step follows the instantaneous wave speed") {
    material.maxwell_relaxation_time_s = 0.1;
    const double c_p = std::sqrt((material.lame_lambda_pa() + 2.0 * material.shear_modulus_pa() +
                                  4.0 / 3.0 * material.shear_modulus_pa()) / material.density_kg_m3);
    CHECK(material.dilatational_wave_speed_m_s() == Approx(c_p).epsilon(1e-12));
    Material elastic = material;
    elastic.maxwell_modulus_ratio = 0.0;
    CHECK(elastic.dilatational_wave_speed_m_s() == Approx(c_equilibrium).epsilon(1e-12));
  }
}

TEST_CASE("Maxwell parameters out of range are refused by name", "[mpm][viscoelasticity]") {
  Material material = SoftMaterial();
  material.maxwell_modulus_ratio = -0.5;
  CHECK_THROWS_WITH(ValidateMaterial(material), Catch::Contains("maxwell_modulus_ratio"));
  material.maxwell_modulus_ratio = 0.5;
  material.maxwell_relaxation_time_s = std::nan("");
  CHECK_THROWS_WITH(ValidateMaterial(material), Catch::Contains("maxwell_relaxation_time_s"));
}

}  // namespace
}  // namespace culinarycut::mpm
