// Step's rollback: a step that may be cancelled saves the food's particles only once the step is about
// to change them, steps exactly like one that may not be cancelled, and when cancelled, asleep or awake,
// leaves the state as it was bit for bit.
#include <catch2/catch.hpp>

#include "sim/policy/scripted_oracle.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"
#include "sim/world/step_rollback.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

SceneConfig DraftCucumber() {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, false, true, true, true, true};
  FoodConfig cucumber;
  cucumber.food = "cucumber";
  config.foods.push_back(cucumber);
  return config;
}

// A cancel check that says stop on its n-th question.
CancelCheck StopOnQuestion(int n) {
  auto asked = std::make_shared<int>(0);
  return [asked, n] { return ++*asked >= n; };
}

}  // namespace

TEST_CASE("a cancellable Step steps bit for bit like a plain one; a cancelled one changes nothing", "[step][rollback]") {
  const auto model = CompileModel(DraftCucumber(), testing::Panda());
  State plain, cancellable;
  ResetState(*model, &plain, 5, {});
  ResetState(*model, &cancellable, 5, {});
  OracleConfig oracle_config;
  oracle_config.instruction = "cut the cucumber in the middle";
  oracle_config.objects = model->food->objects;
  const ScriptedOracle oracle(*model, oracle_config, plain.physics->JointPositions(), plain.sim_time_s);
  const CancelCheck never = [] { return false; };
  int asleep_cancels = 0, awake_cancels = 0;
  // From the approach (food asleep) until well into the cut (food awake, particles moving).
  for (int step = 0; !oracle.Finished(plain.sim_time_s); ++step) {
    if (plain.food->first_contact_frame && plain.frame_id > *plain.food->first_contact_frame + 3) break;
    const Action action{oracle.control_mode(), oracle.Act(*model, plain.physics->JointPositions(), plain.sim_time_s)};
    if (step % 9 == 0) {  // a step cancelled at a different point each time, on a copy
      State cancelled;
      CopyState(*model, plain, &cancelled);
      const bool asleep = !plain.food->awake;
      const StepResult result = Step(*model, &cancelled, action, StopOnQuestion(1 + step % 5));
      REQUIRE(result.cancelled);
      INFO("step " << step << (asleep ? " (food asleep)" : " (food awake)"));
      CHECK_FALSE(FirstStateDifference(*model, plain, cancelled).has_value());
      (asleep ? asleep_cancels : awake_cancels) += 1;
    }
    Step(*model, &plain, action);
    const StepResult result = Step(*model, &cancellable, action, never);
    CHECK(result.timings[Stage::kRollback] > 0.0);
    INFO("step " << step);
    REQUIRE_FALSE(FirstStateDifference(*model, plain, cancellable).has_value());
  }
  CHECK(asleep_cancels > 0);
  CHECK(awake_cancels > 0);
}

TEST_CASE("the rollback saves the food's particles only when the step would change them", "[step][rollback]") {
  const auto model = CompileModel(DraftCucumber(), testing::Panda());
  State state;
  ResetState(*model, &state, 1, {});
  REQUIRE_FALSE(state.food->awake);
  StepRollback rollback(*model, state);
  const std::size_t without_body = rollback.saved_bytes();
  CHECK(without_body < 2048);  // the robot and the food's scalars
  rollback.BeforeFoodBodyChanges(*state.food);
  const std::size_t with_body = rollback.saved_bytes();
  CHECK(with_body > 10 * state.food->solver->particles().size());  // positions alone are 12 bytes each
  rollback.BeforeFoodBodyChanges(*state.food);  // saved once
  CHECK(rollback.saved_bytes() == with_body);
  // A robot-only step with the food asleep and the knife far: the rollback never saves the particles.
  State copy;
  CopyState(*model, state, &copy);
  const StepResult result = Step(*model, &copy, Action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)},
                                 [] { return false; });
  CHECK(result.mpm_substeps == 0);
  CHECK(result.timings[Stage::kRollback] < result.wall_time_ms);
}
