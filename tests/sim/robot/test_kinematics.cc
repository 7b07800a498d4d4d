#include <catch2/catch.hpp>

#include <cmath>

#include "sim/robot/kinematics.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

// Craig's modified DH link transform: Rx(alpha) Tx(a) Rz(theta) Tz(d).
Eigen::Isometry3d ModifiedDh(double a, double d, double alpha, double theta) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitX()));
  t.translate(Eigen::Vector3d(a, 0, 0));
  t.rotate(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()));
  t.translate(Eigen::Vector3d(0, 0, d));
  return t;
}

// The flange pose straight from the Panda's published DH table.
Eigen::Isometry3d FlangeFromDhTable(const Eigen::VectorXd& q) {
  const double table[8][3] = {{0, 0.333, 0},       {0, 0, -M_PI / 2},      {0, 0.316, M_PI / 2},
                              {0.0825, 0, M_PI / 2}, {-0.0825, 0.384, -M_PI / 2}, {0, 0, M_PI / 2},
                              {0.088, 0, M_PI / 2},  {0, 0.107, 0}};
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 8; ++i) pose = pose * ModifiedDh(table[i][0], table[i][1], table[i][2], i < 7 ? q[i] : 0.0);
  return pose;
}

}  // namespace

TEST_CASE("forward kinematics equals the DH table at random configurations", "[kinematics]") {
  std::mt19937_64 rng(7);
  const RobotDescription& robot = testing::Panda();
  for (int sample = 0; sample < 50; ++sample) {
    const Eigen::VectorXd q = testing::RandomJointPositions(&rng);
    const Eigen::Isometry3d expected = FlangeFromDhTable(q);
    const Eigen::Isometry3d actual = TipPose(robot, q, robot.TipFrame("panda_link8"));
    INFO("sample " << sample);
    CHECK((actual.translation() - expected.translation()).norm() < 1e-6);
    CHECK((actual.linear() - expected.linear()).norm() < 1e-6);
  }
}

TEST_CASE("the Jacobian matches finite differences of forward kinematics", "[kinematics]") {
  std::mt19937_64 rng(11);
  const RobotDescription& robot = testing::Panda();
  const Eigen::Isometry3d& tcp = robot.TipFrame("knife_tcp");
  const double h = 1e-7;
  for (int sample = 0; sample < 10; ++sample) {
    const Eigen::VectorXd q = testing::RandomJointPositions(&rng, 0.01);
    const Jacobian jacobian = TipJacobian(robot, q, tcp);
    for (int j = 0; j < robot.dof(); ++j) {
      Eigen::VectorXd q_plus = q;
      q_plus[j] += h;
      const Eigen::Vector3d velocity = (TipPose(robot, q_plus, tcp).translation() - TipPose(robot, q, tcp).translation()) / h;
      CHECK((velocity - jacobian.block<3, 1>(0, j)).norm() < 1e-5);
    }
  }
}

TEST_CASE("the knife TCP sits below the flange in the ready pose", "[kinematics]") {
  const RobotDescription& robot = testing::Panda();
  const Eigen::VectorXd q = testing::DefaultModel()->initial_qpos_rad;
  const Eigen::Isometry3d flange = TipPose(robot, q, robot.TipFrame("panda_link8"));
  const Eigen::Isometry3d tcp = TipPose(robot, q, robot.TipFrame("knife_tcp"));
  // Knife down: flange z axis points to -z world; the edge is 0.13 m out along it.
  CHECK(flange.linear().col(2).z() == Approx(-1.0).margin(1e-9));
  CHECK((flange.inverse() * tcp).translation().z() == Approx(0.13).margin(1e-9));
  CHECK(tcp.translation().z() < flange.translation().z());
}

TEST_CASE("gravity torques are the gradient of the arm's potential energy", "[kinematics]") {
  std::mt19937_64 rng(13);
  const RobotDescription& robot = testing::Panda();
  const Eigen::Vector3d gravity(0, 0, -9.81);
  // V(q) = -sum m_j g . com_j(q); holding torques are dV/dq.
  auto potential = [&](const Eigen::VectorXd& q) {
    std::vector<Eigen::Isometry3d> poses;
    ForwardKinematics(robot, q, &poses);
    double energy = 0.0;
    for (int j = 0; j < robot.dof(); ++j) energy -= robot.links[j].mass_kg * gravity.dot(poses[j] * robot.links[j].center_of_mass_m);
    return energy;
  };
  const double h = 1e-6;
  for (int sample = 0; sample < 10; ++sample) {
    const Eigen::VectorXd q = testing::RandomJointPositions(&rng, 0.01);
    const Eigen::VectorXd torques = GravityTorques(robot, q, gravity);
    for (int i = 0; i < robot.dof(); ++i) {
      Eigen::VectorXd plus = q, minus = q;
      plus[i] += h;
      minus[i] -= h;
      CHECK(torques[i] == Approx((potential(plus) - potential(minus)) / (2 * h)).margin(1e-5));
    }
    CHECK(torques[0] == Approx(0.0).margin(1e-9));  // joint 1's axis is vertical
  }
}
