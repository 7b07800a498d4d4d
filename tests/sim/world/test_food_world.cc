// The robot, the MPM food and the coupling between them, at the draft preset: a robot-only scene
// builds no MPM, the food sleeps until the knife comes near, and an oracle cut through a cucumber
// leaves two pieces with a force on the knife only while it is in the food.
#include <catch2/catch.hpp>

#include "sim/policy/scripted_oracle.h"
#include "sim/world/food_step.h"
#include "sim/world/observation.h"
#include "sim/world/step.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

SceneConfig CucumberScene(bool topology) {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, false, true, true, topology, true};
  FoodConfig cucumber;
  cucumber.food = "cucumber";  // its real material preset
  config.foods.push_back(cucumber);
  return config;
}

struct CutTrace {
  std::vector<double> force_n;       // |wrench| per control step
  std::vector<int> mpm_substeps;
  std::vector<task::SegmentPhase> phase;
  std::size_t pieces = 0;
  std::optional<std::uint64_t> first_contact_frame;
};

CutTrace RunOracleCut(const Model& model, const std::string& instruction) {
  State state;
  ResetState(model, &state, 3, {});
  OracleConfig oracle_config;
  oracle_config.instruction = instruction;
  oracle_config.objects = model.food->objects;
  const ScriptedOracle oracle(model, oracle_config, state.physics->JointPositions(), state.sim_time_s);
  CutTrace trace;
  while (!oracle.Finished(state.sim_time_s)) {
    trace.phase.push_back(oracle.PhaseAt(state.sim_time_s));
    const Eigen::VectorXd action = oracle.Act(model, state.physics->JointPositions(), state.sim_time_s);
    const StepResult report = Step(model, &state, Action{oracle.control_mode(), action});
    trace.force_n.push_back(state.food->control_step_wrench.force_n.norm());
    trace.mpm_substeps.push_back(report.mpm_substeps);
  }
  UpdatePieces(*model.food, state.food.get());
  trace.pieces = state.food->pieces.size();
  trace.first_contact_frame = state.food->first_contact_frame;
  return trace;
}

double MeanX(const mpm::Particles<float>& particles) {  // m
  double sum_m = 0.0;
  for (const float x : particles.position[0]) sum_m += x;
  return sum_m / particles.size();
}

}  // namespace

TEST_CASE("a robot-only scene builds no MPM", "[food_world]") {
  const auto model = testing::DefaultModel();
  CHECK_FALSE(model->food.has_value());
  State state;
  ResetState(*model, &state, 0, {});
  CHECK(state.food == nullptr);
  const StepResult report = Step(*model, &state, Action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)});
  CHECK(report.mpm_substeps == 0);
}

TEST_CASE("food without effects.mpm and effects without food are refused with the field named", "[food_world]") {
  SceneConfig config = CucumberScene(false);
  config.effects.mpm = false;
  CHECK_THROWS_WITH(CompileModel(config, testing::Panda()), Catch::Contains("effects.mpm"));
  SceneConfig no_food;
  no_food.effects.damage = true;
  CHECK_THROWS_WITH(CompileModel(no_food, testing::Panda()), Catch::Contains("effects.damage"));
  SceneConfig bad_food = CucumberScene(false);
  bad_food.foods[0].food = "durian";
  CHECK_THROWS_WITH(CompileModel(bad_food, testing::Panda()), Catch::Contains("scene.objects[0]"));
  SceneConfig bad_override = CucumberScene(false);
  bad_override.foods[0].material_overrides["stiffness"] = 1.0;
  CHECK_THROWS_WITH(CompileModel(bad_override, testing::Panda()), Catch::Contains("youngs_modulus_pa"));
}

TEST_CASE("the food rests on the board with its long axis left-right", "[food_world]") {
  const auto model = CompileModel(CucumberScene(false), testing::Panda());
  REQUIRE(model->food.has_value());
  const task::ObjectBox& box = model->food->objects.at(0);
  CHECK(box.name == "cucumber_0");
  const task::LongAxis axis = task::LongAxisOf(box);
  CHECK(std::abs(axis.direction.y()) == Approx(1.0));
  const double board_top_m = model->layout.board_center_m.z() + 0.5 * model->layout.board_size_m.z();
  CHECK(task::BottomZ(box) == Approx(board_top_m).margin(1e-9));
}

TEST_CASE("the food sleeps until the knife comes near", "[food_world]") {
  const auto model = CompileModel(CucumberScene(false), testing::Panda());
  State state;
  ResetState(*model, &state, 0, {});
  for (int i = 0; i < 3; ++i) {
    const StepResult report = Step(*model, &state, Action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)});
    CHECK(report.mpm_substeps == 0);
  }
  CHECK(state.food->substeps == 0);
  CHECK_FALSE(state.food->awake);
}

TEST_CASE("the food wakes when the knife comes within 2.5 grid cells at any dx", "[food_world]") {
  // A particle's quadratic stencil reaches 1.5 cells: within that the knife can touch the food's grid.
  SceneConfig config = CucumberScene(false);
  CHECK(CompileModel(config, testing::Panda())->food->activation_margin_m == Approx(0.020));
  config.mpm.dx_m = 0.006;
  CHECK(CompileModel(config, testing::Panda())->food->activation_margin_m == Approx(0.015));
}

TEST_CASE("an oracle cut through a cucumber leaves two pieces and loads the knife only in contact", "[food_world]") {
  const auto model = CompileModel(CucumberScene(true), testing::Panda());
  const CutTrace trace = RunOracleCut(*model, "cut the cucumber in the middle");
  CHECK(trace.pieces == 2);
  REQUIRE(trace.first_contact_frame.has_value());
  const std::size_t contact = *trace.first_contact_frame - 1;  // index of the step it happened in
  // Before the knife gets near, MPM does not run and the knife feels nothing.
  CHECK(trace.mpm_substeps.at(0) == 0);
  double before_n = 0.0, during_n = 0.0;
  for (std::size_t i = 0; i < contact; ++i) before_n = std::max(before_n, trace.force_n[i]);
  for (std::size_t i = contact; i < trace.force_n.size(); ++i) during_n = std::max(during_n, trace.force_n[i]);
  CHECK(before_n < 1e-6);
  CHECK(during_n > 1.0);
}

TEST_CASE("the engine scores the scene's task: reward, success and termination come with the step that cuts",
          "[food_world]") {
  SceneConfig config = CucumberScene(true);
  config.task.instruction = "cut the cucumber in the middle";
  const auto model = testing::DefaultModel(config);
  REQUIRE(model->task.has_value());
  State state;
  ResetState(*model, &state, 3, {});
  const Observation before = Observe(*model, state);
  CHECK(before.instruction == "cut the cucumber in the middle");
  REQUIRE(before.task_score.has_value());
  CHECK_FALSE(before.task_score->success);

  OracleConfig oracle_config;
  oracle_config.spec = model->task->spec;
  oracle_config.objects = model->food->objects;
  const ScriptedOracle oracle(*model, oracle_config, state.physics->JointPositions(), state.sim_time_s);
  StepResult last;
  int steps_before_success = 0;
  while (!oracle.Finished(state.sim_time_s) && !last.terminated) {
    const Eigen::VectorXd action = oracle.Act(*model, state.physics->JointPositions(), state.sim_time_s);
    last = Step(*model, &state, Action{oracle.control_mode(), action});
    REQUIRE(last.task_score.has_value());
    CHECK(last.reward == (last.success ? 1.0 : 0.0));
    CHECK(last.terminated == last.success);
    if (!last.success) ++steps_before_success;
  }
  CHECK(last.success);
  CHECK(last.terminated);
  CHECK(steps_before_success > 0);
  const Observation after = Observe(*model, state);
  REQUIRE(after.task_score.has_value());
  CHECK(after.task_score->success);
  REQUIRE(after.food.has_value());
  CHECK(after.food->pieces.size() >= 2);
}

TEST_CASE("an episode's solver reads the model's settings and materials, never a copy", "[food_world]") {
  const auto model = testing::DefaultModel(CucumberScene(false));
  State a, b;
  ResetState(*model, &a, 0, {});
  ResetState(*model, &b, 1, {});
  for (const State* state : {&a, &b}) {
    CHECK(&state->food->solver->config() == &model->food->solver->config);
    CHECK(&state->food->solver->materials() == &model->food->solver->materials);
  }
}

TEST_CASE("food thrown faster than its sound takes shorter MPM substeps and its step still ends on time",
          "[food_world]") {
  SceneConfig config = CucumberScene(false);
  config.foods[0].material_overrides["youngs_modulus_pa"] = 5e3;  // sound slower than the throw
  const auto model = CompileModel(config, testing::Panda());
  const mpm::SolverModel& solver_model = *model->food->solver;
  const double speed_m_s = 10.0;
  REQUIRE(solver_model.materials[0].dilatational_wave_speed_m_s() < 0.5 * speed_m_s);
  const double duration_s = model->physics_timestep_s;
  // The knife 1 m above the food, still; the food awake, so MPM runs for it alone.
  Eigen::Isometry3d knife = Eigen::Isometry3d::Identity();
  knife.translation() = Eigen::Vector3d(0.5, 0.0, 1.0);
  auto fresh_food = [&](State* state) {
    ResetState(*model, state, 0, {});
    state->food->awake = true;
  };
  auto throw_sideways = [&](FoodState* food) {
    for (float& v : food->solver->particles().velocity[0]) v = static_cast<float>(speed_m_s);
  };
  const int at_rest = static_cast<int>(std::ceil(duration_s / mpm::StableTimestep(solver_model)));
  // Thrown before the step: every substep at most a CFL fraction of a cell at 10 m/s.
  const double cfl_dx_m = solver_model.config.cfl * solver_model.config.dx_m;
  const int thrown_substeps = static_cast<int>(std::ceil(duration_s * speed_m_s / cfl_dx_m));
  REQUIRE(thrown_substeps > at_rest + 1);
  REQUIRE(at_rest >= 2);  // a step of one substep has nothing left to split again
  State resting, thrown, mid_step;
  fresh_food(&resting);
  CHECK(AdvanceFood(*model->food, knife, knife, duration_s, resting.food.get()).substeps == at_rest);
  fresh_food(&thrown);
  throw_sideways(thrown.food.get());
  const FoodStepReport report = AdvanceFood(*model->food, knife, knife, duration_s, thrown.food.get());
  CHECK(report.substeps >= thrown_substeps);  // gravity adds a little speed
  CHECK(report.substeps <= thrown_substeps + 1);
  // Thrown once the step has chosen its substeps (by the cancel check, asked before each substep):
  // the first substep is as long as at rest; then the rest of the step is split again at the
  // shorter bound, and the step still covers its whole duration.
  fresh_food(&mid_step);
  int asked = 0;
  const FoodStepReport split = AdvanceFood(*model->food, knife, knife, duration_s, mid_step.food.get(), [&] {
    if (++asked == 1) throw_sideways(mid_step.food.get());
    return false;
  });
  CHECK(split.substeps == asked);
  CHECK(split.substeps >= 1 + static_cast<int>(std::ceil(duration_s * (1.0 - 1.0 / at_rest) * speed_m_s / cfl_dx_m)));
  // Its substeps add up to the step: it flew at 10 m/s (less a little board friction) for all of it.
  const double flown_m = MeanX(mid_step.food->solver->particles()) - MeanX(resting.food->solver->particles());
  CHECK(flown_m == Approx(speed_m_s * duration_s).epsilon(0.01));
}
