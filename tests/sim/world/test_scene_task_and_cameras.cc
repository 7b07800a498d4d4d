// The scene's task and cameras as the model compiles them: default specs, errors naming the field,
// and the task score from the food's pieces (crumbs left out).
#include <catch2/catch.hpp>

#include "sim/world/model.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

namespace {

SceneConfig CucumberTaskScene(TaskConfig task) {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, false, true, false, true, false};
  config.foods.push_back(FoodConfig{"cucumber"});
  config.task = std::move(task);
  return config;
}

// A piece of `object` spanning [from, to] of its long axis (fractions from the left end), 2 cm thick
// across it, lying where it was cut (its rest bounds, which the score reads, are its bounds).
mpm::Piece PieceAlong(const task::ObjectBox& object, double from, double to, std::size_t particles) {
  const task::LongAxis axis = task::LongAxisOf(object);
  const Eigen::Vector3d a = task::PointAtFraction(axis, from), b = task::PointAtFraction(axis, to);
  const Eigen::Vector3d across_m = Eigen::Vector3d::Constant(0.01) - 0.01 * axis.direction.cwiseAbs();
  mpm::Piece piece;
  piece.particle_count = particles;
  piece.bounds_m.extend(a.cwiseMin(b) - across_m);
  piece.bounds_m.extend(a.cwiseMax(b) + across_m);
  piece.rest_bounds_m = piece.bounds_m;
  return piece;
}

}  // namespace

TEST_CASE("A task from spec fields follows the paper's defaults and targets the scene's only food") {
  const auto model = CompileModel(CucumberTaskScene(TaskConfig{"", "", "ratio", 0.3, 0, "", "left"}), testing::Panda());
  REQUIRE(model->task);
  CHECK(model->task->spec.style == task::CutStyle::kNormal);
  CHECK(model->task->spec.target_object == "cucumber");
  CHECK_FALSE(model->task->instruction.empty());
  CHECK(model->config.task.cut_style == "normal");  // echoed resolved
}

TEST_CASE("Bad tasks are refused with the field named") {
  const auto compile = [](TaskConfig task) { CompileModel(CucumberTaskScene(std::move(task)), testing::Panda()); };
  CHECK_THROWS_WITH(compile(TaskConfig{"cut the cucumber in half", "", "middle"}), Catch::Contains("not both"));
  CHECK_THROWS_WITH(compile(TaskConfig{"", "", "ratio"}), Catch::Contains("scene.task.ratio"));
  CHECK_THROWS_WITH(compile(TaskConfig{"", "", "middle", 0, 0, "melon"}), Catch::Contains("targets melon"));
}

TEST_CASE("The task score comes from the pieces: a cut at 0.3 succeeds, a crumb is no cut") {
  const mpm::Particles<float> kNoParticles;  // no cut records: position-only cuts
  const mpm::CutProgress kNoCuts;
  const auto model = CompileModel(CucumberTaskScene(TaskConfig{"cut the cucumber at 0.3 ratio from the left"}),
                                  testing::Panda());
  const task::ObjectBox& cucumber = model->food->objects.at(0);
  const std::size_t total = model->task->object_particles.at(0);
  FoodState state;
  state.pieces = {PieceAlong(cucumber, 0.0, 0.31, total * 3 / 10), PieceAlong(cucumber, 0.33, 1.0, total * 7 / 10)};
  task::TaskScore score = EvaluateTask(*model->task, *model->food, state.pieces, kNoParticles, kNoCuts);
  CHECK(score.success);
  REQUIRE(score.required.size() == 1);
  CHECK(score.required[0].measured_fraction == Approx(0.32).margin(1e-6));

  state.pieces.push_back(PieceAlong(cucumber, 0.9, 0.92, total / 100));  // a 1 % crumb: left out
  CHECK(EvaluateTask(*model->task, *model->food, state.pieces, kNoParticles, kNoCuts).success);
  state.pieces.back().particle_count = total / 10;  // a 10 % slice: an extra cut fails the task
  CHECK_FALSE(EvaluateTask(*model->task, *model->food, state.pieces, kNoParticles, kNoCuts).success);

  state.pieces = {PieceAlong(cucumber, 0.0, 1.0, total)};  // uncut
  score = EvaluateTask(*model->task, *model->food, state.pieces, kNoParticles, kNoCuts);
  CHECK_FALSE(score.success);
  CHECK_FALSE(score.required[0].placed);
}

TEST_CASE("Default cameras need only a name; others need a pose; channels and sizes are checked") {
  SceneConfig config;
  config.cameras = {CameraConfig{"front"}, CameraConfig{"wrist"}};
  config.cameras[0].channels = {"depth", "segmentation"};
  config.cameras[1].width = 96;
  const auto model = CompileModel(config, testing::Panda());
  REQUIRE(model->cameras.size() == 2);
  CHECK_FALSE(model->cameras[0].rgb);
  CHECK(model->cameras[0].depth);
  CHECK(model->cameras[0].width == 224);
  CHECK(model->cameras[1].attached_link == "panda_link8");
  CHECK(model->cameras[1].width == 96);
  CHECK(model->config.cameras[1].pose.has_value());  // echoed resolved

  const auto refused = [](CameraConfig camera) {
    SceneConfig scene;
    scene.cameras = {std::move(camera)};
    CompileModel(scene, testing::Panda());
  };
  CHECK_THROWS_WITH(refused(CameraConfig{"top"}), Catch::Contains("needs a pose"));
  CameraConfig infrared{"front"};
  infrared.channels = {"infrared"};
  CHECK_THROWS_WITH(refused(infrared), Catch::Contains("scene.cameras[0].channels"));
  CameraConfig huge{"front"};
  huge.height = 4096;
  CHECK_THROWS_WITH(refused(huge), Catch::Contains("scene.cameras[0].height"));
}
