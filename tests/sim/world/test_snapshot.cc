#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "sim/world/observation.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {
std::vector<Eigen::VectorXd> Rollout(const Model& model, State* state, int steps) {
  std::vector<Eigen::VectorXd> trajectory;
  for (int i = 0; i < steps; ++i) {
    const double phase = 0.3 * i;
    Action action{ControlMode::kEndEffectorDeltaPose,
                  (Eigen::VectorXd(6) << 0.1 * std::sin(phase), 0.1 * std::cos(phase), -0.05, 0, 0, 0.2).finished()};  // normalised
    Step(model, state, action);
    const RobotObservation observation = ObserveRobot(model, *state);
    Eigen::VectorXd row(14);
    row << observation.qpos_rad, observation.qvel_rad_s;
    trajectory.push_back(row);
  }
  return trajectory;
}
}  // namespace

TEST_CASE("restoring a snapshot replays the same trajectory bit for bit", "[snapshot]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 1, {});
  Rollout(*model, &state, 10);
  const std::string snapshot = SaveSnapshot(*model, state);
  const auto first = Rollout(*model, &state, 30);
  RestoreSnapshot(*model, snapshot, &state);
  CHECK(state.frame_id == 10);
  const auto second = Rollout(*model, &state, 30);
  for (size_t i = 0; i < first.size(); ++i) {
    INFO("step " << i);
    CHECK(first[i] == second[i]);
  }
}

TEST_CASE("corrupt or foreign snapshots are refused and change nothing", "[snapshot]") {
  const auto model = testing::DefaultModel();
  State state;
  ResetState(*model, &state, 1, {});
  const std::string good = SaveSnapshot(*model, state);
  Rollout(*model, &state, 2);
  const RobotObservation before = ObserveRobot(*model, state);
  CHECK_THROWS_AS(RestoreSnapshot(*model, "garbage", &state), SnapshotError);
  CHECK_THROWS_AS(RestoreSnapshot(*model, good.substr(0, good.size() - 3), &state), SnapshotError);
  SceneConfig other;
  other.robot.control_frequency_hz = 10.0;
  CHECK_THROWS_WITH(RestoreSnapshot(*testing::DefaultModel(other), good, &state), Catch::Contains("different scene"));
  // A well-formed snapshot whose joint values were overwritten: NaN, and far outside the limits.
  const size_t first_qpos = good.size() - 3 * (sizeof(std::uint32_t) + 7 * sizeof(double)) + sizeof(std::uint32_t);
  for (double bad : {std::nan(""), 50.0}) {
    std::string poisoned = good;
    std::memcpy(&poisoned[first_qpos], &bad, sizeof(double));
    CHECK_THROWS_WITH(RestoreSnapshot(*model, poisoned, &state), Catch::Contains("joint 0"));
  }
  CHECK(ObserveRobot(*model, state).qpos_rad == before.qpos_rad);
  CHECK(state.frame_id == 2);
}

TEST_CASE("the state comparison names the first field that differs", "[snapshot]") {
  const auto model = testing::DefaultModel();
  State a, b;
  ResetState(*model, &a, 4, {});
  ResetState(*model, &b, 4, {});
  CHECK_FALSE(FirstStateDifference(*model, a, b).has_value());
  Rollout(*model, &a, 3);
  Rollout(*model, &b, 3);
  CHECK_FALSE(FirstStateDifference(*model, a, b).has_value());  // same seed and actions: same bits
  b.q_target_rad[2] += 1e-12;
  CHECK(FirstStateDifference(*model, a, b) == std::optional<std::string>("robot.q_target_rad"));
  Rollout(*model, &b, 1);
  CHECK(FirstStateDifference(*model, a, b) == std::optional<std::string>("frame_id"));
}

TEST_CASE("a copied state is independent and steps exactly like its source", "[snapshot]") {
  const auto model = testing::DefaultModel();
  State source, copy;
  ResetState(*model, &source, 2, {});
  Rollout(*model, &source, 5);
  CopyState(*model, source, &copy);
  CHECK_FALSE(FirstStateDifference(*model, source, copy).has_value());
  CHECK(copy.physics.get() != source.physics.get());
  const auto from_source = Rollout(*model, &source, 10);
  const auto from_copy = Rollout(*model, &copy, 10);
  CHECK(from_source == from_copy);
  CHECK_FALSE(FirstStateDifference(*model, source, copy).has_value());
}
