#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "sim/robot/kinematics.h"
#include "sim/world/controller.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {
Action MakeAction(ControlMode mode, std::vector<double> values) {
  return Action{mode, Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<long>(values.size()))};
}
}  // namespace

TEST_CASE("control modes round-trip through their names", "[controller]") {
  for (ControlMode mode : AllControlModes()) CHECK(ParseControlMode(ControlModeName(mode)) == mode);
  CHECK_FALSE(ParseControlMode("pd_ee_twist").has_value());
}

TEST_CASE("bad actions are rejected with a message naming the element", "[controller]") {
  const auto model = testing::DefaultModel();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK_THAT(*ValidateAction(*model, MakeAction(ControlMode::kJointPosition, {0, 0, 0})),
             Catch::Contains("action.values") && Catch::Contains("7"));
  CHECK_THAT(*ValidateAction(*model, MakeAction(ControlMode::kJointDeltaPosition, {0, 0, nan, 0, 0, 0, 0})),
             Catch::Contains("action.values[2]") && Catch::Contains("NaN"));
  CHECK_THAT(*ValidateAction(*model, MakeAction(ControlMode::kEndEffectorDeltaPose, {0, inf, 0, 0, 0, 0})),
             Catch::Contains("action.values[1]"));
  CHECK_THAT(*ValidateAction(*model, MakeAction(ControlMode::kEndEffectorPose, {0.5, 0, 0.2, 0, 0, 0, 0})),
             Catch::Contains("quaternion"));
  CHECK_FALSE(ValidateAction(*model, MakeAction(ControlMode::kEndEffectorPose, {0.5, 0, 0.2, 0, 1, 0, 0})).has_value());
}

TEST_CASE("out-of-bound actions are clipped and flagged", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const JointTarget big = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointDeltaPosition, {1, 0, 0, 0, 0, 0, 0}));
  CHECK(big.clipped);
  CHECK(big.q_target_rad[0] == Approx(q[0] + 0.1));
  const JointTarget small = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointDeltaPosition, {0.05, 0, 0, 0, 0, 0, 0}));
  CHECK_FALSE(small.clipped);
  const JointTarget beyond = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointPosition, {9, 0, 0, -1, 0, 1, 0}));
  CHECK(beyond.clipped);
  CHECK(beyond.q_target_rad[0] == Approx(model->robot.limits[0].upper_rad));
}

TEST_CASE("pd_ee_pose takes a quaternion of any norm as its direction, unclipped", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const JointTarget scaled = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorPose, {0.5, 0, 0.2, 0, 2, 0.2, 0}));
  const JointTarget unit = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorPose, {0.5, 0, 0.2, 0, 1, 0.1, 0}));
  CHECK_FALSE(scaled.clipped);
  CHECK((scaled.q_target_rad - unit.q_target_rad).norm() < 1e-12);
  // Entries whose squares overflow or underflow a double still mean the same direction.
  for (double magnitude : {1e200, 1e-200}) {
    const Action extreme = MakeAction(ControlMode::kEndEffectorPose, {0.5, 0, 0.2, 0, magnitude, 0.1 * magnitude, 0});
    CHECK_FALSE(ValidateAction(*model, extreme).has_value());
    CHECK((ComputeJointTarget(*model, q, extreme).q_target_rad - unit.q_target_rad).norm() < 1e-12);
  }
}

TEST_CASE("pd_ee_delta_pose targets the TCP moved by the delta", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const JointTarget target = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorDeltaPose, {0, 0, -0.05, 0, 0, 0}));
  REQUIRE(target.ik.has_value());
  CHECK(target.ik->converged);
  const Eigen::Vector3d before = TipPose(model->robot, q, model->tcp_in_last_link).translation();
  const Eigen::Vector3d after = TipPose(model->robot, target.q_target_rad, model->tcp_in_last_link).translation();
  CHECK((after - before - Eigen::Vector3d(0, 0, -0.05)).norm() < 1e-4);
}

TEST_CASE("the velocity command respects the joint speed limits and keeps its direction", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const Eigen::VectorXd error = (Eigen::VectorXd(7) << 2.0, -1.0, 0.5, 2.0, 0.1, -3.0, 0.0).finished();
  const Eigen::VectorXd command = JointVelocityCommand(*model, q, q + error);
  double largest_ratio = 0.0;
  for (int i = 0; i < 7; ++i) {
    CHECK(std::abs(command[i]) <= model->robot.limits[i].max_velocity_rad_s + 1e-12);
    largest_ratio = std::max(largest_ratio, std::abs(command[i]) / model->robot.limits[i].max_velocity_rad_s);
  }
  CHECK(largest_ratio == Approx(1.0));  // as fast as the most limited joint allows
  CHECK(command.normalized().dot(error.normalized()) == Approx(1.0));  // parallel to the error
  // Small errors are not scaled: the plain PD law.
  const Eigen::VectorXd small = JointVelocityCommand(*model, q, q + Eigen::VectorXd::Constant(7, 1e-3));
  CHECK((small - Eigen::VectorXd::Constant(7, 1e-3 * model->config.robot.joint_stiffness_per_s)).norm() < 1e-12);
}
