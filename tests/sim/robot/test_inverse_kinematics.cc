#include <catch2/catch.hpp>

#include "sim/core/pose.h"
#include "sim/robot/inverse_kinematics.h"
#include "sim/robot/kinematics.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

TEST_CASE("IK recovers reachable poses near the seed and stays inside the joint limits", "[ik]") {
  std::mt19937_64 rng(3);
  const RobotDescription& robot = testing::Panda();
  const Eigen::Isometry3d& tcp = robot.TipFrame("knife_tcp");
  const Eigen::VectorXd ready = testing::DefaultModel()->initial_qpos_rad;
  std::uniform_real_distribution<double> offset(-0.4, 0.4);
  for (int sample = 0; sample < 30; ++sample) {
    Eigen::VectorXd q_goal = ready;
    for (int i = 0; i < q_goal.size(); ++i) q_goal[i] += offset(rng);
    q_goal = ClampToJointLimits(robot, q_goal, 0.01);
    const Eigen::Isometry3d target = TipPose(robot, q_goal, tcp);
    const IkResult result = SolveInverseKinematics(robot, tcp, target, ready);
    INFO("sample " << sample);
    CHECK(result.converged);
    const Eigen::Isometry3d reached = TipPose(robot, result.q_rad, tcp);
    CHECK((reached.translation() - target.translation()).norm() < 1e-4);
    CHECK(AngleBetween(reached.linear(), target.linear()) < 1e-3);
    for (int i = 0; i < robot.dof(); ++i) {
      CHECK(result.q_rad[i] >= robot.limits[i].lower_rad);
      CHECK(result.q_rad[i] <= robot.limits[i].upper_rad);
    }
  }
}

TEST_CASE("IK toward an unreachable pose returns the closest in-limit configuration, unconverged", "[ik]") {
  const RobotDescription& robot = testing::Panda();
  const Eigen::Isometry3d& tcp = robot.TipFrame("knife_tcp");
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 3.0, 0.0, 0.5;  // 3 m away: beyond the arm's reach
  const IkResult result = SolveInverseKinematics(robot, tcp, far, testing::DefaultModel()->initial_qpos_rad);
  CHECK_FALSE(result.converged);
  CHECK(result.position_error_m > 1.0);
  CHECK(result.q_rad.allFinite());
  for (int i = 0; i < robot.dof(); ++i) {
    CHECK(result.q_rad[i] >= robot.limits[i].lower_rad);
    CHECK(result.q_rad[i] <= robot.limits[i].upper_rad);
  }
}
