// The food's force on the arm stays passive along each knife axis (passive_coupling.h).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "sim/world/passive_coupling.h"

namespace culinarycut {
namespace {

const Eigen::Matrix3d kAxes = Eigen::Matrix3d::Identity();
constexpr double kTimestepS = 0.002;

TEST_CASE("a force that resists the knife passes unchanged; one that drives it is held to what the food absorbed",
          "[world][coupling]") {
  const Eigen::Vector3d velocity(0.0, 0.1, -0.05);  // m/s
  const Eigen::Vector3d resisting(0.0, -3.0, 20.0);   // N, against the motion on every axis
  CHECK(PassiveCouplingForce(resisting, kAxes, velocity, kTimestepS, Eigen::Vector3d::Zero()).isApprox(resisting));
  const Eigen::Vector3d driving(0.0, 5.0, 20.0);  // sideways along the motion: 0.5 W on the arm
  const Eigen::Vector3d empty = PassiveCouplingForce(driving, kAxes, velocity, kTimestepS, Eigen::Vector3d::Zero());
  CHECK(empty.y() == 0.0);
  CHECK(empty.z() == 20.0);
  // 0.4 mJ absorbed sideways allows 0.2 W over 2 ms: 2 N at 0.1 m/s.
  const Eigen::Vector3d some = PassiveCouplingForce(driving, kAxes, velocity, kTimestepS, {0.0, 4e-4, 0.0});
  CHECK(some.y() == Approx(2.0));
  // The axes are the knife's: the same force and motion turned with the knife give the same answer turned.
  const Eigen::Matrix3d turned = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  CHECK((turned * some).isApprox(PassiveCouplingForce(turned * driving, turned, turned * velocity, kTimestepS,
                                                      {0.0, 4e-4, 0.0})));
}

TEST_CASE("booked work: what the arm does against the food is absorbed, what the food gives back is spent",
          "[world][coupling]") {
  Eigen::Vector3d absorbed = Eigen::Vector3d::Zero();
  BookCouplingWork({0.0, 0.0, 20.0}, kAxes, {0.0, 0.0, -0.001}, &absorbed);  // pushed 1 mm into 20 N
  CHECK(absorbed.z() == Approx(0.02));
  BookCouplingWork({0.0, 0.0, 20.0}, kAxes, {0.0, 0.0, 0.0005}, &absorbed);  // 0.5 mm of spring-back
  CHECK(absorbed.z() == Approx(0.01));
  CHECK(absorbed.head<2>().isZero());
}

// A knife of mass m in a stiff slot (k), pushed off its rest position, coupled as the world couples
// it: the food's force is its mean over the step the knife just moved (here the spring at the mean
// position) and acts on the knife during the next step. That lag feeds the oscillation unless the
// coupling is passive.
double AmplitudeAfter(int steps, bool passive) {
  const double mass_kg = 0.5, stiffness_n_m = 5e3, start_m = 1e-4;
  double x = start_m, v = 0.0, force = -stiffness_n_m * x;
  Eigen::Vector3d absorbed = Eigen::Vector3d::Zero();
  double amplitude = 0.0;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector3d felt = passive ? PassiveCouplingForce({0.0, force, 0.0}, kAxes, {0.0, v, 0.0}, kTimestepS, absorbed)
                                         : Eigen::Vector3d(0.0, force, 0.0);
    v += felt.y() / mass_kg * kTimestepS;
    const double x_before = x;
    x += v * kTimestepS;
    BookCouplingWork(felt, kAxes, {0.0, x - x_before, 0.0}, &absorbed);
    force = -stiffness_n_m * 0.5 * (x_before + x);
    if (i > steps - 200) amplitude = std::max(amplitude, std::abs(x));
  }
  return amplitude / start_m;
}

TEST_CASE("a lagged stiff slot pumps a knife's oscillation up; the passive coupling lets it die out", "[world][coupling]") {
  CHECK(AmplitudeAfter(1000, false) > 10.0);
  CHECK(AmplitudeAfter(1000, true) <= 1.0);
}

}  // namespace
}  // namespace culinarycut
