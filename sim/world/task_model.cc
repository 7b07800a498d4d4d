#include "sim/world/task_model.h"

#include <array>
#include <optional>
#include <set>
#include <utility>

#include "sim/task/instruction_generator.h"
#include "sim/task/cut_plane_fit.h"
#include "sim/task/instruction_parser.h"
#include "sim/mpm/cut_record.h"
#include "sim/world/model.h"

namespace culinarycut {
namespace {

// The scene's only food type, for a task that names none.
std::string OnlyFood(const FoodModel& food) {
  std::set<std::string> foods;
  for (const task::ObjectBox& object : food.objects) foods.insert(object.food);
  if (foods.size() != 1) {
    throw SceneError("scene.task.target_object is needed: the scene has " + std::to_string(foods.size()) +
                     " kinds of food");
  }
  return *foods.begin();
}

task::CutSpec SpecFromFields(const TaskConfig& config, const FoodModel& food) {
  task::PartialCutSpec partial;
  if (!config.cut_style.empty()) partial.style = task::CutStyleFromName(config.cut_style);
  if (!config.cut_state.empty()) partial.state = task::CutStateFromName(config.cut_state);
  if (partial.state == task::CutState::kRatio && config.ratio == 0.0) {
    throw SceneError("scene.task.ratio is needed for a ratio cut (0.1-0.9 of the length from `reference`)");
  }
  if (partial.state == task::CutState::kSplit && config.split_pieces == 0) {
    throw SceneError("scene.task.split_pieces is needed for a split cut (3, 4 or 5)");
  }
  if (config.ratio != 0.0) partial.ratio = config.ratio;
  if (config.split_pieces != 0) partial.split_pieces = config.split_pieces;
  partial.target_object = config.target_object.empty() ? OnlyFood(food) : config.target_object;
  if (!config.reference.empty()) partial.reference = task::DirectionalReferenceFromName(config.reference);
  return task::ResolveDefaults(partial);
}

// A cut recorded in an object: the surface it left and the blade's orientation while it was made.
struct RecordedCut {
  task::FittedPlane surface;
  std::optional<Eigen::Vector3d> blade_normal;
};

// Every cut recorded in each object with at least two pieces (objects without are skipped: nothing
// there was parted): its surface plane, fitted to where the particles the edge passed on either side
// of the blade were sampled (material coordinates, like the pieces' bounds), and the blade's mean
// normal from the knife's pose while the edge passed food in that cut.
std::vector<std::vector<RecordedCut>> RecordedCuts(const mpm::Particles<float>& particles,
                                                   const mpm::CutProgress& progress,
                                                   const std::vector<bool>& parted_object) {
  using Sides = std::array<std::vector<Eigen::Vector3d>, 2>;  // negative, positive
  std::vector<std::array<Sides, mpm::kMaxRecordedCuts>> sides_of(parted_object.size());
  for (std::size_t q = 0; q < particles.size(); ++q) {
    const std::uint32_t record = particles.cut_sides[q];
    const std::uint16_t object = particles.object[q];
    if (record == 0 || object >= parted_object.size() || !parted_object[object]) continue;
    const Eigen::Vector3d rest_m(particles.rest_position[0][q], particles.rest_position[1][q],
                                 particles.rest_position[2][q]);
    for (int cut = 0; cut < mpm::kMaxRecordedCuts; ++cut) {
      if (!(record & mpm::PassedBit(cut))) continue;
      sides_of[object][cut][(record & mpm::PositiveSideBit(cut)) ? 1 : 0].push_back(rest_m);
    }
  }
  std::vector<std::vector<RecordedCut>> cuts(parted_object.size());
  for (std::size_t object = 0; object < parted_object.size(); ++object) {
    for (int cut = 0; cut < mpm::kMaxRecordedCuts; ++cut) {
      const Sides& sides = sides_of[object][cut];
      if (const std::optional<task::FittedPlane> plane = task::FitCutPlane(sides[1], sides[0])) {
        cuts[object].push_back({*plane, progress.blade_normals[cut].MeanNormal()});
      }
    }
  }
  return cuts;
}

// Gives `cut` (a position between two pieces) the orientations of the recorded cut whose surface
// crosses the long axis nearest to it, if one does within `reach` (a fraction of the length); else
// it stays position-only.
void AttachRecordedCut(const task::LongAxis& axis, const std::vector<RecordedCut>& recorded, double reach,
                       task::MeasuredCut* cut) {
  const std::optional<double> at = task::CutFractionAlongAxis(axis, *cut);
  double nearest = reach;
  for (const RecordedCut& candidate_cut : recorded) {
    task::MeasuredCut candidate = *cut;
    candidate.plane_point_m = candidate_cut.surface.point_m;
    candidate.plane_normal = candidate_cut.surface.normal;
    const std::optional<double> crossing = task::CutFractionAlongAxis(axis, candidate);
    if (!at || !crossing || !(std::abs(*crossing - *at) <= nearest)) continue;
    nearest = std::abs(*crossing - *at);
    cut->plane_normal = candidate_cut.surface.normal;
    cut->blade_normal = candidate_cut.blade_normal;
  }
}

}  // namespace

TaskModel CompileTask(const TaskConfig& config, const FoodModel& food, std::uint64_t seed) {
  TaskModel model;
  try {
    if (!config.instruction.empty()) {
      if (config.has_spec_fields()) {
        throw SceneError("scene.task: give either instruction or the cut spec fields, not both");
      }
      model.spec = task::ParseInstruction(config.instruction);
      model.instruction = config.instruction;
    } else {
      model.spec = SpecFromFields(config, food);
    }
  } catch (const task::TaskError& error) {
    throw SceneError(std::string(config.instruction.empty() ? "scene.task: " : "scene.task.instruction: ") +
                     error.what());
  }
  int matches = 0;
  for (std::size_t i = 0; i < food.objects.size(); ++i) {
    if (food.objects[i].food != model.spec.target_object) continue;
    if (matches++ == 0) model.target_object = static_cast<int>(i);
  }
  if (matches != 1) {
    throw SceneError("scene.task targets " + model.spec.target_object + ", but the scene has " +
                     std::to_string(matches) + " of it; a task needs exactly one target object");
  }
  if (model.instruction.empty()) {
    try {
      model.instruction = task::GenerateInstructions(model.spec, seed, 1, task::LanguageSplit::kTrain).front();
    } catch (const task::TaskError&) {
      model.instruction = task::Describe(model.spec);  // no template says this spec
    }
  }
  model.description = task::Describe(model.spec);
  model.object_particles.assign(food.objects.size(), 0);
  for (std::uint16_t object : food.initial_particles.object) ++model.object_particles[object];
  return model;
}

task::TaskScore EvaluateTask(const TaskModel& task, const FoodModel& food, const std::vector<mpm::Piece>& pieces,
                             const mpm::Particles<float>& particles, const mpm::CutProgress& cut_progress) {
  std::vector<std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> bounds_of_object(food.objects.size());
  for (const mpm::Piece& piece : pieces) {
    const double share = static_cast<double>(piece.particle_count) / std::max<std::size_t>(1, task.object_particles[piece.object]);
    if (share < task.min_piece_fraction) continue;  // a crumb, not a piece
    // Where the pieces' material came from, not where it lies now: the cut is placed where the blade
    // passed, however far the pieces slid or rolled since.
    bounds_of_object[piece.object].emplace_back(piece.rest_bounds_m.min(), piece.rest_bounds_m.max());
  }
  std::vector<bool> parted_object(food.objects.size());
  for (std::size_t i = 0; i < food.objects.size(); ++i) parted_object[i] = bounds_of_object[i].size() >= 2;
  const std::vector<std::vector<RecordedCut>> recorded = RecordedCuts(particles, cut_progress, parted_object);
  std::vector<task::MeasuredCut> cuts;
  for (std::size_t i = 0; i < food.objects.size(); ++i) {
    const task::LongAxis axis = task::LongAxisOf(food.objects[i]);
    for (task::MeasuredCut& cut : task::CutsFromPieceBounds(food.objects[i], bounds_of_object[i])) {
      AttachRecordedCut(axis, recorded[i], task.tolerances.position_fraction, &cut);
      cuts.push_back(std::move(cut));
    }
  }
  return task::ScoreCuts(food.objects[static_cast<std::size_t>(task.target_object)], task.spec, cuts, task.tolerances);
}

}  // namespace culinarycut
