#include "tools/cc_cut/cut_model.h"

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

#include "server/wire/field_error.h"
#include "server/wire/scene.h"
#include "sim/core/stage_timer.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/specimen_shapes.h"
#include "sim/task/object_box.h"
#include "tools/cc_cut/json_object_reader.h"

namespace culinarycut::cc_cut {
namespace {

// What a server scene may hold that needs a robot, a renderer or an episode: cc-cut has none.
void RejectUnsimulated(const v1::SceneSpec& spec) {
  if (spec.has_robot()) FailField("scene.robot", "cc-cut has no robot: the knife follows the knife block");
  if (spec.cameras_size() > 0) FailField("scene.cameras", "cc-cut renders nothing");
  if (spec.has_task()) FailField("scene.task", "cc-cut has no task: the knife block says where to cut");
  if (spec.max_episode_steps() != 0) {
    FailField("scene.max_episode_steps", "cc-cut has no episode: knife.max_time_s bounds the run");
  }
  if (!spec.scene().empty()) FailField("scene.scene", "the furniture's look matters only to cameras; cc-cut renders nothing");
  if (spec.objects_size() != 1) {
    FailField("scene.objects", "cc-cut cuts one food object; give exactly one, got " + std::to_string(spec.objects_size()));
  }
}

void CheckCutPosition(const KnifePath& knife, const task::ObjectBox& food) {
  if (!knife.cut_from_centre_m) return;
  const double half_length_m = 0.5 * task::LongAxisOf(food).length_m;
  if (!(*knife.cut_from_centre_m > -half_length_m && *knife.cut_from_centre_m < half_length_m)) {
    FailField("knife.cut_from_centre_m", "must lie within the food, in (" + ShowNumber(-half_length_m) + ", " +
                                             ShowNumber(half_length_m) + ") m, got " +
                                             ShowNumber(*knife.cut_from_centre_m));
  }
}

}  // namespace

CutModel CompileCut(const CutScene& scene) {
  RejectUnsimulated(scene.scene);
  CutModel model;
  try {
    model.config = server::SceneFromWire(scene.scene);
  } catch (const server::UnimplementedField& unavailable) {
    throw std::invalid_argument(unavailable.what());
  }
  if (const auto error = ValidateSceneConfig(model.config)) throw std::invalid_argument(*error);
  if (scene.specimen) {
    try {
      mpm::MakeSpecimenShape(scene.specimen->kind, scene.specimen->size_m);  // checked here to name the field
    } catch (const std::invalid_argument& error) {
      FailField("specimen", error.what());
    }
    model.config.foods.front().specimen = scene.specimen;
  }
  const auto start = std::chrono::steady_clock::now();
  model.food = CompileFoodModel(model.config, model.layout);
  model.compile_ms = MillisecondsSince(start);

  // The model's solver settings are shared and read-only: the overrides go into a copy.
  mpm::SolverModel solver = *model.food.solver;
  ApplySolverOverrides(scene.solver, &solver.config);
  try {
    mpm::ValidateSolverConfig(solver.config);
  } catch (const std::invalid_argument& error) {
    FailField("solver", error.what());
  }
  model.food.solver = std::make_shared<const mpm::SolverModel>(std::move(solver));
  CheckCutPosition(scene.knife, model.food.objects.front());
  model.knife = scene.knife;
  return model;
}

v1::SceneSpec ResolvedSceneSpec(const CutModel& model) {
  v1::SceneSpec spec = server::SceneToWire(model.config);
  server::ResolvedFoodToWire(model.food, &spec);
  spec.clear_robot();
  spec.clear_scene();  // the furniture's look: for cameras only
  return spec;
}

}  // namespace culinarycut::cc_cut
