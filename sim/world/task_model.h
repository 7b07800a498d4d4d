// The scene's cutting task (paper, "Task Definition"), compiled with the model, and its score
// against the food's current pieces (paper, "Success Criteria"). Each object's pieces give cuts
// midway between neighbouring pieces along its long axis; each takes the orientation of the cut
// surface the blade left there (fitted to the material it labelled either side, sim/task/cut_plane_fit.h)
// and of the blade while its edge passed the food there; all are scored against the required cuts on
// the target object.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/mpm/cut_record.h"
#include "sim/task/cut_spec.h"
#include "sim/task/success_metrics.h"
#include "sim/world/food_model.h"
#include "sim/world/food_state.h"
#include "sim/world/scene_config.h"

namespace culinarycut {

struct TaskModel {
  task::CutSpec spec;
  std::string instruction;   // as given, or generated from the spec (train language, scene seed)
  std::string description;   // one line, e.g. "normal cut, ratio 0.3 from the left, cucumber"
  int target_object = 0;     // index into FoodModel::objects
  task::SuccessTolerances tolerances;
  // Pieces smaller than this share of their object's particles are crumbs, not cut pieces: the
  // smallest piece a task asks for (a 0.1 ratio slice) is 10 % of the object.
  double min_piece_fraction = 0.03;
  std::vector<std::size_t> object_particles;  // particles of each food object at rest
};

// Throws SceneError naming the field: both an instruction and spec fields, an instruction that
// cannot be parsed, an invalid spec, or a target food that is not in the scene (or is ambiguous).
TaskModel CompileTask(const TaskConfig& config, const FoodModel& food, std::uint64_t seed);

// The task's score now, from the pieces of the last topology update, the particles' cut records and
// the blade's orientation in each cut.
task::TaskScore EvaluateTask(const TaskModel& task, const FoodModel& food, const std::vector<mpm::Piece>& pieces,
                             const mpm::Particles<float>& particles, const mpm::CutProgress& cut_progress);

}  // namespace culinarycut
