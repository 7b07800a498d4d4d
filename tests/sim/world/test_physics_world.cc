#include <catch2/catch.hpp>

#include "sim/robot/kinematics.h"
#include "sim/world/controller.h"
#include "sim/world/physics_world.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

TEST_CASE("Bullet's link frames agree with the kinematic model", "[physics]") {
  std::mt19937_64 rng(5);
  const RobotDescription& robot = testing::Panda();
  PhysicsWorld world(robot, SceneLayout{}, 0.002);
  for (int sample = 0; sample < 20; ++sample) {
    const Eigen::VectorXd q = testing::RandomJointPositions(&rng);
    world.SetJointState(q, Eigen::VectorXd::Zero(7));
    std::vector<Eigen::Isometry3d> expected;
    ForwardKinematics(robot, q, &expected);
    for (int link = 0; link < robot.dof(); ++link) {
      INFO("sample " << sample << " link " << link);
      CHECK((world.LinkPose(link).translation() - expected[link].translation()).norm() < 1e-9);
      CHECK((world.LinkPose(link).linear() - expected[link].linear()).norm() < 1e-9);
    }
    CHECK((world.JointPositions() - q).norm() == 0.0);
  }
}

TEST_CASE("the PD loop holds the arm against gravity and without it the arm sags", "[physics]") {
  const auto model = testing::DefaultModel();
  const Eigen::VectorXd q0 = model->initial_qpos_rad;
  PhysicsWorld held(model->robot, SceneLayout{}, 0.002);
  PhysicsWorld unheld(model->robot, SceneLayout{}, 0.002);
  held.SetJointState(q0, Eigen::VectorXd::Zero(7));
  unheld.SetJointState(q0, Eigen::VectorXd::Zero(7));
  for (int i = 0; i < 500; ++i) {  // 1 s
    held.SetJointVelocityCommand(JointVelocityCommand(*model, held.JointPositions(), q0));
    held.StepOnce();
    unheld.SetJointVelocityCommand(Eigen::VectorXd::Zero(7));  // velocity servo alone: no position feedback
    unheld.StepOnce();
  }
  const double held_error = (held.JointPositions() - q0).cwiseAbs().maxCoeff();
  const double unheld_error = (unheld.JointPositions() - q0).cwiseAbs().maxCoeff();
  CHECK(held_error < 5e-4);  // ~0.4 mm at the TCP: the velocity-servo steady-state sag
  CHECK(unheld_error > 5 * held_error);
}
