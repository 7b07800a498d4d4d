#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "sim/core/pose.h"
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
  CHECK_THAT(*ValidateAction(*model, MakeAction(ControlMode::kEndEffectorPoseQuat, {0.5, 0, 0.2, 0, 0, 0, 0})),
             Catch::Contains("quaternion"));
  CHECK_FALSE(ValidateAction(*model, MakeAction(ControlMode::kEndEffectorPoseQuat, {0.5, 0, 0.2, 0, 1, 0, 0})).has_value());
}

TEST_CASE("out-of-bound actions are clipped and flagged", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  // pd_joint_delta_pos is normalised: [-1, 1] means +-0.1 rad, beyond is clipped.
  const JointTarget big = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointDeltaPosition, {10, 0, 0, 0, 0, 0, 0}));
  CHECK(big.clipped);
  CHECK(big.q_target_rad[0] == Approx(q[0] + 0.1));
  const JointTarget small = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointDeltaPosition, {0.5, 0, 0, 0, 0, 0, 0}));
  CHECK_FALSE(small.clipped);
  CHECK(small.q_target_rad[0] == Approx(q[0] + 0.05));
  const JointTarget beyond = ComputeJointTarget(*model, q, MakeAction(ControlMode::kJointPosition, {9, 0, 0, -1, 0, 1, 0}));
  CHECK(beyond.clipped);
  CHECK(beyond.q_target_rad[0] == Approx(model->robot.limits[0].upper_rad));
}

TEST_CASE("pd_ee_pose_quat takes a quaternion of any norm as its direction, unclipped", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const JointTarget scaled = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorPoseQuat, {0.5, 0, 0.2, 0, 2, 0.2, 0}));
  const JointTarget unit = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorPoseQuat, {0.5, 0, 0.2, 0, 1, 0.1, 0}));
  CHECK_FALSE(scaled.clipped);
  CHECK((scaled.q_target_rad - unit.q_target_rad).norm() < 1e-12);
  // Entries whose squares overflow or underflow a double still mean the same direction.
  for (double magnitude : {1e200, 1e-200}) {
    const Action extreme = MakeAction(ControlMode::kEndEffectorPoseQuat, {0.5, 0, 0.2, 0, magnitude, 0.1 * magnitude, 0});
    CHECK_FALSE(ValidateAction(*model, extreme).has_value());
    CHECK((ComputeJointTarget(*model, q, extreme).q_target_rad - unit.q_target_rad).norm() < 1e-12);
  }
}

TEST_CASE("pd_ee_delta_pose targets the TCP moved by the delta", "[controller]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  // Normalised as in ManiSkill: -0.5 means 0.05 m down.
  const JointTarget target = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorDeltaPose, {0, 0, -0.5, 0, 0, 0}));
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

// The ManiSkill meaning of each mode (ManiSkill3 panda_stick; PDEEPoseController, frame
// "root_translation:root_aligned_body_rotation"). The robot's root frame is the base frame.
TEST_CASE("a normalised pd_ee_delta_pose of +1 along x moves the TCP 0.1 m along the root x axis", "[controller][maniskill]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const Eigen::Isometry3d before = TipPose(model->robot, q, model->tcp_in_last_link);
  for (const ControlMode mode : {ControlMode::kEndEffectorDeltaPose, ControlMode::kEndEffectorDeltaPosition}) {
    std::vector<double> values = {1, 0, 0};
    if (mode == ControlMode::kEndEffectorDeltaPose) values.resize(6, 0.0);
    const JointTarget target = ComputeJointTarget(*model, q, MakeAction(mode, values));
    CHECK_FALSE(target.clipped);
    const Eigen::Isometry3d after = TipPose(model->robot, target.q_target_rad, model->tcp_in_last_link);
    CHECK((after.translation() - before.translation() - Eigen::Vector3d(0.1, 0, 0)).norm() < 1e-4);
    CHECK(AngleBetween(after.linear(), before.linear()) < 1e-4);  // orientation held
  }
}

TEST_CASE("pd_ee_delta_pose rotates about the TCP with root-aligned axes, XYZ Euler, and clips the rotation by its norm",
          "[controller][maniskill]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const Eigen::Isometry3d before = TipPose(model->robot, q, model->tcp_in_last_link);
  // +1 about root z: the TCP turns 0.1 rad about the root z axis, in place.
  const JointTarget turn = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorDeltaPose, {0, 0, 0, 0, 0, 1}));
  const Eigen::Isometry3d after = TipPose(model->robot, turn.q_target_rad, model->tcp_in_last_link);
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix() * before.linear();
  CHECK(AngleBetween(after.linear(), expected) < 1e-4);
  CHECK((after.translation() - before.translation()).norm() < 1e-4);
  // A rotation input of norm 2 is scaled back onto the unit ball, keeping its direction.
  const JointTarget big = ComputeJointTarget(*model, q, MakeAction(ControlMode::kEndEffectorDeltaPose, {0, 0, 0, 0, 0, 2}));
  CHECK(big.clipped);
  CHECK((big.q_target_rad - turn.q_target_rad).norm() < 1e-9);
}

TEST_CASE("pd_ee_pose takes a position and XYZ Euler angles in the root frame", "[controller][maniskill]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q = model->initial_qpos_rad;
  const Eigen::Isometry3d start = TipPose(model->robot, q, model->tcp_in_last_link);
  const Eigen::Vector3d euler = EulerXyzFromRotation(start.linear()) + Eigen::Vector3d(0.05, -0.05, 0.1);
  const Eigen::Vector3d position = start.translation() + Eigen::Vector3d(0.02, -0.03, -0.04);
  const JointTarget target = ComputeJointTarget(
      *model, q, MakeAction(ControlMode::kEndEffectorPose, {position.x(), position.y(), position.z(), euler.x(), euler.y(), euler.z()}));
  REQUIRE(target.ik.has_value());
  CHECK(target.ik->converged);
  const Eigen::Isometry3d reached = TipPose(model->robot, target.q_target_rad, model->tcp_in_last_link);
  CHECK((reached.translation() - position).norm() < 1e-4);
  CHECK(AngleBetween(reached.linear(), RotationFromEulerXyz(euler)) < 1e-4);
}

TEST_CASE("XYZ Euler angles are Rx Ry Rz and round-trip", "[controller][maniskill]") {
  const Eigen::Vector3d angles(0.3, -0.4, 1.2);
  const Eigen::Matrix3d r = RotationFromEulerXyz(angles);
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                                   Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                                   Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  CHECK((r - expected).norm() < 1e-12);
  CHECK((EulerXyzFromRotation(r) - angles).norm() < 1e-12);
}
