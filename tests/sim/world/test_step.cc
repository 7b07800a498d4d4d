#include <catch2/catch.hpp>

#include "sim/core/pose.h"
#include "sim/robot/kinematics.h"
#include "sim/world/observation.h"
#include "sim/world/step.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

Action PoseAction(const Eigen::Isometry3d& pose) { return Action{ControlMode::kEndEffectorPoseQuat, PoseToVector(pose)}; }

// Reachable knife poses: the TCP of joint configurations near the ready pose, above the table.
std::vector<Eigen::Isometry3d> RandomReachableTargets(const Model& model, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  std::vector<Eigen::Isometry3d> targets;
  while (static_cast<int>(targets.size()) < count) {
    Eigen::VectorXd q = model.initial_qpos_rad;
    for (int i = 0; i < q.size(); ++i) q[i] += offset(rng);
    q = ClampToJointLimits(model.robot, q, 0.05);
    const Eigen::Isometry3d tcp = model.robot_base_in_world * TipPose(model.robot, q, model.tcp_in_last_link);
    if (tcp.translation().z() > 0.08) targets.push_back(tcp);
  }
  return targets;
}

}  // namespace

TEST_CASE("pd_ee_pose_quat reaches random targets within 1 mm and 1 degree in 3 s, inside the joint limits", "[step]") {
  const auto model = testing::DefaultModel();
  const int max_steps = static_cast<int>(3.0 / model->control_timestep_s);
  int index = 0;
  for (const Eigen::Isometry3d& target : RandomReachableTargets(*model, 24, 17)) {
    State state;
    ResetState(*model, &state, 0, {});
    double position_error = 1e9, angle_error = 1e9;
    for (int step = 0; step < max_steps; ++step) {
      Step(*model, &state, PoseAction(target));
      const RobotObservation observation = ObserveRobot(*model, state);
      for (int j = 0; j < 7; ++j) {
        REQUIRE(observation.qpos_rad[j] >= model->robot.limits[j].lower_rad);
        REQUIRE(observation.qpos_rad[j] <= model->robot.limits[j].upper_rad);
      }
      const Eigen::Isometry3d tcp = PoseFromVector(observation.tcp_pose);
      position_error = (tcp.translation() - target.translation()).norm();
      angle_error = AngleBetween(tcp.linear(), target.linear());
      if (position_error < 1e-3 && angle_error < M_PI / 180) break;
    }
    INFO("target " << index++ << " at " << target.translation().transpose());
    CHECK(position_error < 1e-3);
    CHECK(angle_error < M_PI / 180);
  }
}

TEST_CASE("a step advances the frame id and the sim time by one control period", "[step]") {
  SceneConfig config;
  config.max_episode_steps = 3;
  const auto model = testing::DefaultModel(config);
  State state;
  ResetState(*model, &state, 42, {});
  const Action hold{ControlMode::kJointDeltaPosition, Eigen::VectorXd::Zero(7)};
  StepResult report;
  for (int i = 0; i < 3; ++i) {
    CHECK_FALSE(report.truncated);
    report = Step(*model, &state, hold);
  }
  CHECK(report.truncated);
  CHECK(report.substeps == 25);
  CHECK(state.frame_id == 3);
  CHECK(state.sim_time_s == Approx(0.15));
}

TEST_CASE("same seed and actions give identical observations", "[step]") {
  const auto model = testing::DefaultModel();
  State a, b;
  ResetState(*model, &a, 9, {});
  ResetState(*model, &b, 9, {});
  const Action action{ControlMode::kEndEffectorDeltaPose, (Eigen::VectorXd(6) << 0.1, -0.2, -0.3, 0.0, 0.5, 0.0).finished()};  // normalised
  for (int i = 0; i < 20; ++i) {
    Step(*model, &a, action);
    Step(*model, &b, action);
  }
  CHECK(ObserveRobot(*model, a).qpos_rad == ObserveRobot(*model, b).qpos_rad);
  CHECK(ObserveRobot(*model, a).qvel_rad_s == ObserveRobot(*model, b).qvel_rad_s);
}

TEST_CASE("a bad initial qpos at reset is refused with the joint named", "[step]") {
  const auto model = testing::DefaultModel();
  State state;
  CHECK_THROWS_WITH(ResetState(*model, &state, 0, {0, 0, 0, 0, 0, 0, 0}), Catch::Contains("initial_qpos[3]"));
  CHECK_THROWS_WITH(ResetState(*model, &state, 0, {0, 0}), Catch::Contains("7 values"));
  CHECK_FALSE(state.has_been_reset());
}

TEST_CASE("a step reports the time of its stages, which totals accumulate", "[step]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 0, {});
  const StepResult report =
      Step(*model, &state, Action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)});
  CHECK(report.timings[Stage::kControl] > 0);
  CHECK(report.timings[Stage::kPhysics] > 0);
  CHECK(report.timings[Stage::kControl] + report.timings[Stage::kPhysics] <= report.wall_time_ms);
  // A robot-only scene runs no food, topology or task stage.
  CHECK(report.timings[Stage::kMpm] == 0);
  CHECK(report.timings[Stage::kTopology] == 0);
  CHECK(report.timings[Stage::kTask] == 0);
  StageTotals totals;
  totals.Add(report.timings);
  totals.Add(report.timings);
  CHECK(totals.calls[static_cast<int>(Stage::kPhysics)] == 2);
  CHECK(totals.calls[static_cast<int>(Stage::kMpm)] == 0);
  CHECK(totals.wall_s[static_cast<int>(Stage::kPhysics)] * 1e3 == Approx(2 * report.timings[Stage::kPhysics]));
}

TEST_CASE("a robot-only step has no reward, success or task score", "[step]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 0, {});
  const StepResult result = Step(*model, &state, Action{ControlMode::kJointDeltaPosition, Eigen::VectorXd::Zero(7)});
  CHECK(result.reward == 0.0);
  CHECK_FALSE(result.success);
  CHECK_FALSE(result.terminated);
  CHECK_FALSE(result.task_score.has_value());
  const Observation observation = Observe(*model, state);
  CHECK(observation.frame_id == 1);
  CHECK(observation.instruction.empty());
  CHECK_FALSE(observation.food.has_value());
  CHECK(observation.images.cameras.empty());
}

TEST_CASE("with gravity compensation a held pose does not sag", "[step]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 0, {});
  const Eigen::VectorXd q0 = model->initial_qpos_rad;
  const Action hold{ControlMode::kJointPosition, q0};
  for (int i = 0; i < 40; ++i) Step(*model, &state, hold);  // 2 s
  // Without compensation the velocity servo sags ~1e-4 rad (test_physics_world.cc).
  CHECK((ObserveRobot(*model, state).qpos_rad - q0).cwiseAbs().maxCoeff() < 1e-5);
}

TEST_CASE("joints stay inside their limits even when the arm is driven into the table", "[step]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 0, {});
  Eigen::VectorXd lower(7);
  for (int i = 0; i < 7; ++i) lower[i] = model->robot.limits[i].lower_rad;
  // All joints at their lower limits folds the arm onto the table: contact pushes back on the joints.
  for (int step = 0; step < 100; ++step) {
    Step(*model, &state, Action{ControlMode::kJointPosition, lower});
    const Eigen::VectorXd q = ObserveRobot(*model, state).qpos_rad;
    for (int i = 0; i < 7; ++i) REQUIRE(q[i] >= model->robot.limits[i].lower_rad);
  }
}
