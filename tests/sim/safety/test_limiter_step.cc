// The limiter in Step against real MPM food: a fast descent onto a stiff food pushes the knife past
// F_max without the limiter, and stays under it with the limiter on; the limiter off costs no time.
#include <catch2/catch.hpp>

#include <cmath>

#include "force_model_fixture.h"
#include "sim/safety/force_model.h"
#include "sim/world/step.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

SceneConfig StiffFoodScene(double youngs_modulus_pa, double toughness_j_m2, double stiffness_per_s) {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, false, true, true, false, true};
  config.robot.joint_stiffness_per_s = stiffness_per_s;
  FoodConfig food;
  food.food = "cucumber";
  food.scale = 0.6;
  food.material_overrides = {{"youngs_modulus_pa", youngs_modulus_pa}, {"fracture_toughness_j_m2", toughness_j_m2}};
  config.foods.push_back(food);
  return config;
}

// The knife pointing down (TCP +z along world -z), its blade across the food (along world x).
Action KnifeAt(const Eigen::Vector3d& position_m) {
  Eigen::VectorXd values(7);
  values << position_m, 0.0, 1.0, 0.0, 0.0;
  return Action{ControlMode::kEndEffectorPoseQuat, values};
}

struct DescentTrace {
  double peak_force_n = 0.0;
  double peak_speed_m_s = 0.0;
  std::uint64_t interventions = 0;
  int steps = 0;
};

// Puts the knife 3 cm above the food's top, then commands it to just above the board at once.
DescentTrace Descend(const Model& model, int descent_steps) {
  State state;
  ResetState(model, &state, 0, {});
  const task::ObjectBox& food = model.food->objects[0];
  const Eigen::Vector3d top = food.pose.translation() + Eigen::Vector3d(0, 0, 0.5 * food.extent_m.z());
  for (int i = 0; i < 40; ++i) Step(model, &state, KnifeAt(top + Eigen::Vector3d(0, 0, 0.03)));
  REQUIRE(state.food->first_contact_frame == std::nullopt);
  const double board_top_m = model.layout.board_center_m.z() + 0.5 * model.layout.board_size_m.z();
  DescentTrace trace;
  for (int i = 0; i < descent_steps; ++i) {
    Step(model, &state, KnifeAt(Eigen::Vector3d(top.x(), top.y(), board_top_m + 0.004)));
    trace.steps += 1;
  }
  trace.peak_force_n = state.safety.peak_knife_force_n;
  trace.peak_speed_m_s = state.safety.peak_cutting_speed_m_s;
  for (std::uint64_t count : state.safety.interventions) trace.interventions += count;
  return trace;
}


// The test asset: F_hat = G L + 400 v sqrt(E) L. For this food (G = 1000 J/m^2, L about 2.7 cm) even a
// still knife is predicted past 10 N: v_safe = 0, the limiter keeps the knife out of it.
std::shared_ptr<const safety::ForceModel> TestForceModel() {
  return std::make_shared<const safety::ForceModel>(safety::LoadForceModel(CULINARYCUT_TEST_FORCE_MODEL));
}

SceneConfig WithLimiter(SceneConfig config, double max_force_n) {
  config.effects.safety_limiter = true;
  config.safety.max_force_n = max_force_n;
  return config;
}

}  // namespace

TEST_CASE("the limiter keeps a fast descent onto a stiff food under F_max; without it the force passes F_max",
          "[safety][limiter_step]") {
  constexpr double kMaxForceN = 10.0;
  const SceneConfig scene = StiffFoodScene(2.5e6, 1000.0, 40.0);
  const DescentTrace unlimited = Descend(*CompileModel(scene, testing::Panda()), 6);
  CHECK(unlimited.peak_force_n > kMaxForceN);
  CHECK(unlimited.peak_speed_m_s > 0.3);  // the commanded descent is fast
  const DescentTrace limited = Descend(*CompileModel(WithLimiter(scene, kMaxForceN), testing::Panda(), TestForceModel()), 6);
  CHECK(limited.peak_force_n <= kMaxForceN);
  CHECK(limited.interventions >= 1);
}

TEST_CASE("the limiter lets a softer food be cut, slower than v_safe", "[safety][limiter_step]") {
  // Toughness 125 J/m^2: F_hat(0) is about 3.4 N, v_safe for 10 N about 0.4 m/s: the knife enters, capped.
  const SceneConfig scene = WithLimiter(StiffFoodScene(2.5e6, 125.0, 40.0), 10.0);
  const auto model = CompileModel(scene, testing::Panda(), TestForceModel());
  State state;
  ResetState(*model, &state, 0, {});
  const task::ObjectBox& food = model->food->objects[0];
  const Eigen::Vector3d centre = food.pose.translation();
  for (int i = 0; i < 40; ++i) Step(*model, &state, KnifeAt(centre + Eigen::Vector3d(0, 0, 0.05)));
  bool speed_guard_bound = false;
  for (int i = 0; i < 6; ++i) {
    const StepResult result = Step(*model, &state, KnifeAt(Eigen::Vector3d(centre.x(), centre.y(), 0.024)));
    REQUIRE(result.safety.has_value());
    if (result.safety->guard_counts[static_cast<int>(safety::Guard::kSpeed)] == 1) {
      speed_guard_bound = true;
      CHECK(result.safety->v_safe_m_s > 0.1);
      CHECK(result.safety->commanded_speed_m_s > result.safety->v_safe_m_s);
      CHECK_FALSE(result.safety->reason.empty());
    }
  }
  CHECK(speed_guard_bound);
  CHECK(state.food->first_contact_frame.has_value());  // it did enter the food
  CHECK(state.safety.peak_cutting_speed_m_s <= 0.9 * state.safety.v_safe_m_s + 0.05);
}

TEST_CASE("the guards hold motion into the food on force and entry angle, and only then", "[safety][limiter]") {
  const safety::ForceModel model = safety::ParseForceModel(testing::ForceModelDocument({{1.0, {0, 0, 0, 1, 1}}}).dump());
  safety::LimiterSettings settings;
  settings.max_force_n = 10.0;
  safety::LimiterInputs inputs;
  inputs.foods_near_edge.push_back(safety::CutMaterial{2.5, 300, 125, 0.03});
  CHECK_FALSE(safety::LimitIntoFood(settings, model, inputs).holds());
  inputs.knife_force_n = 9.5;  // above (1 - 0.1) 10 N
  safety::IntoFoodLimit limit = safety::LimitIntoFood(settings, model, inputs);
  CHECK(limit.holding[static_cast<int>(safety::Guard::kForce)]);
  CHECK_THAT(limit.hold_reason, Catch::Contains("knife force"));
  inputs.knife_force_n = 0.0;
  inputs.blade_tilt_deg = 20.0;
  limit = safety::LimitIntoFood(settings, model, inputs);
  CHECK(limit.holding[static_cast<int>(safety::Guard::kEntryAngle)]);
  CHECK_THAT(limit.hold_reason, Catch::Contains("tilted"));
  settings.guards = {true, true, false};  // the entry-angle guard off
  CHECK_FALSE(safety::LimitIntoFood(settings, model, inputs).holds());
  inputs.foods_near_edge.clear();  // tilted far from any food: not entering, nothing to guard
  settings.guards = {true, true, true};
  CHECK_FALSE(safety::LimitIntoFood(settings, model, inputs).holds());
  CHECK(std::isinf(safety::LimitIntoFood(settings, model, inputs).max_speed_m_s));
}

TEST_CASE("the limiter off adds no stage and no time", "[safety][limiter_step]") {
  const auto model = CompileModel(StiffFoodScene(2.5e6, 125.0, 40.0), testing::Panda());
  CHECK_FALSE(model->limiter.has_value());
  State state;
  ResetState(*model, &state, 0, {});
  const StepResult result = Step(*model, &state, KnifeAt(model->food->objects[0].pose.translation() + Eigen::Vector3d(0, 0, 0.05)));
  CHECK_FALSE(result.safety.has_value());
  CHECK(result.timings[Stage::kSafety] == 0.0);
}
