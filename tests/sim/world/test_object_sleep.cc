// With several foods, only the one the knife comes near is simulated: a resting distractor sleeps
// (frozen, a fixed load on the grid) through a cut beside it, wakes whole when the knife nears it, and
// a snapshot taken with it asleep replays bit for bit.
#include <catch2/catch.hpp>

#include <cstring>

#include "sim/policy/scripted_oracle.h"
#include "sim/world/food_step.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

constexpr std::uint16_t kCucumber = 0;
constexpr std::uint16_t kMelon = 1;  // the distractor

// A cucumber on the board and a distractor resting 28 cm to its right, as the multi-object suite lays
// them out.
SceneConfig Scene(const std::string& distractor_food = "melon") {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, false, true, true, true, true};
  config.foods.push_back(FoodConfig{"cucumber"});
  FoodConfig distractor{distractor_food};
  distractor.board_xy_m = Eigen::Vector2d(0.50, -0.28);
  config.foods.push_back(distractor);
  return config;
}

struct Objects {
  std::size_t particles[2] = {0, 0};
  std::size_t asleep[2] = {0, 0};
};

Objects Count(const mpm::Particles<float>& p) {
  Objects count;
  for (std::size_t q = 0; q < p.size(); ++q) {
    ++count.particles[p.object[q]];
    count.asleep[p.object[q]] += p.activity.size() == p.size() && p.activity[q] == mpm::kFrozen;
  }
  return count;
}

// The oracle's cut through the cucumber, `steps` control steps of it (all: 0); the peak knife force (N).
double OracleCut(const Model& model, State* state, int steps = 0, std::vector<std::size_t>* active = nullptr) {
  OracleConfig oracle_config;
  oracle_config.instruction = "cut the cucumber in the middle";
  oracle_config.objects = model.food->objects;
  const ScriptedOracle oracle(model, oracle_config, state->physics->JointPositions(), state->sim_time_s);
  double peak_n = 0.0;
  for (int i = 0; (steps == 0 || i < steps) && !oracle.Finished(state->sim_time_s); ++i) {
    const Eigen::VectorXd action = oracle.Act(model, state->physics->JointPositions(), state->sim_time_s);
    Step(model, state, Action{oracle.control_mode(), action});
    peak_n = std::max(peak_n, state->food->control_step_wrench.force_n.norm());
    if (active && state->food->awake) active->push_back(state->food->solver->active_count());
  }
  return peak_n;
}

}  // namespace

TEST_CASE("a resting melon beside the cucumber sleeps through its cut, unmoved", "[food_world][object_sleep]") {
  const auto model = CompileModel(Scene(), testing::Panda());
  State state;
  ResetState(*model, &state, 3, {});
  std::vector<std::size_t> active;
  OracleCut(*model, &state, 0, &active);

  const Objects count = Count(state.food->solver->particles());
  REQUIRE(count.particles[kMelon] > 5 * count.particles[kCucumber]);  // the melon would be most of the work
  CHECK(count.asleep[kMelon] == count.particles[kMelon]);
  CHECK(count.asleep[kCucumber] == 0);
  REQUIRE_FALSE(active.empty());
  for (const std::size_t integrated : active) CHECK(integrated <= count.particles[kCucumber]);
  // Asleep, the melon has not moved at all: every particle where the model sampled it.
  const mpm::Particles<float>& now = state.food->solver->particles();
  std::size_t moved = 0;
  for (std::size_t q = 0; q < now.size(); ++q) {
    if (now.object[q] != kMelon) continue;
    bool same = true;
    for (int axis = 0; axis < 3; ++axis) same = same && now.rest_position[axis][q] == now.position[axis][q];
    moved += !same;
  }
  CHECK(moved == 0);
  UpdatePieces(*model->food, state.food.get());
  CHECK(state.food->pieces.size() == 3);  // the cucumber's two and the melon whole
}

TEST_CASE("the cut beside a sleeping orange is the cut beside one simulated", "[food_world][object_sleep]") {
  const auto model = CompileModel(Scene("orange"), testing::Panda());
  Model awake = *model;
  awake.food->objects_sleep = false;
  State asleep_state, awake_state;
  ResetState(*model, &asleep_state, 3, {});
  ResetState(awake, &awake_state, 3, {});
  const double asleep_n = OracleCut(*model, &asleep_state);
  const double awake_n = OracleCut(awake, &awake_state);
  CHECK(Count(asleep_state.food->solver->particles()).asleep[kMelon] > 0);
  CHECK(Count(awake_state.food->solver->particles()).asleep[kMelon] == 0);
  // The same peak force (what differs is the order the cucumber's particles are summed in, reordered
  // around the frozen ones) and the same pieces.
  CHECK(asleep_n == Approx(awake_n).epsilon(1e-3));
  UpdatePieces(*model->food, asleep_state.food.get());
  UpdatePieces(*awake.food, awake_state.food.get());
  CHECK(asleep_state.food->pieces.size() == awake_state.food->pieces.size());
}

TEST_CASE("a sleeping food wakes whole when the knife comes near it", "[food_world][object_sleep]") {
  const auto model = CompileModel(Scene(), testing::Panda());
  State state;
  ResetState(*model, &state, 3, {});
  OracleCut(*model, &state, 60);  // into the cucumber: the food is awake, the melon asleep
  REQUIRE(state.food->awake);
  REQUIRE(Count(state.food->solver->particles()).asleep[kMelon] > 0);
  // The knife's edge (its TCP) 1 cm above the melon's top, at rest.
  const task::ObjectBox& melon = model->food->objects.at(kMelon);
  Eigen::Isometry3d above = Eigen::Isometry3d::Identity();
  above.linear() = state.food->solver->knife()->motion().pose.linear();
  above.translation() = melon.pose.translation() + Eigen::Vector3d(0.0, 0.0, 0.5 * melon.extent_m.z() + 0.01);
  AdvanceFood(*model->food, above, above, 0.002, state.food.get(), {}, {});
  CHECK(Count(state.food->solver->particles()).asleep[kMelon] == 0);
}

TEST_CASE("a snapshot taken with a food asleep replays the cut bit for bit", "[food_world][object_sleep][snapshot]") {
  const auto model = CompileModel(Scene(), testing::Panda());
  State state;
  ResetState(*model, &state, 3, {});
  OracleCut(*model, &state, 60);
  REQUIRE(Count(state.food->solver->particles()).asleep[kMelon] > 0);
  const std::string snapshot = SaveSnapshot(*model, state);
  State replay;
  ResetState(*model, &replay, 3, {});
  RestoreSnapshot(*model, snapshot, &replay);
  OracleCut(*model, &state, 20);
  OracleCut(*model, &replay, 20);
  const auto& a = state.food->solver->particles();
  const auto& b = replay.food->solver->particles();
  REQUIRE(a.size() == b.size());
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(std::memcmp(a.position[axis].data(), b.position[axis].data(), a.size() * sizeof(float)) == 0);
  }
  CHECK(state.food->control_step_wrench.force_n == replay.food->control_step_wrench.force_n);
}
