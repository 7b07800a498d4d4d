// The compiled food part of a Model: the MPM solver settings, one material per food object, the
// initial particle set and each object's box for the task logic. Absent (std::nullopt in Model)
// when the scene declares no MPM, so a robot-only scene allocates nothing of it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/mpm/colliders.h"
#include "sim/mpm/materials.h"
#include "sim/mpm/particles.h"
#include "sim/mpm/solver.h"
#include "sim/mpm/solver_config.h"
#include "sim/mpm/topology.h"
#include "sim/task/object_box.h"
#include "sim/world/quality_preset.h"
#include "sim/world/scene_budget.h"
#include "sim/world/scene_config.h"
#include "sim/core/scene_layout.h"

namespace culinarycut {

struct FoodModel {
  MpmResolution resolution;
  // Solver settings and materials (materials[i] belongs to object i), shared with every episode's
  // solver; never null in a compiled model.
  std::shared_ptr<const mpm::SolverModel> solver;
  mpm::Particles<float> initial_particles;   // at rest, undeformed; copied into each episode
  std::vector<task::ObjectBox> objects;      // objects[i]: name "<food>_<i>", pose and extent at rest
  mpm::KnifeGeometry knife;                  // in the knife TCP frame (matches the robot's knife)
  mpm::TopologyOptions topology;
  bool topology_update = false;              // detect pieces after every control step
  double particle_spacing_m = 0.0;           // dx / ppc^(1/3)
  // MPM wakes up when the knife comes within this distance (m) of the food's bounding box
  // (kActivationMarginCells grid cells).
  double activation_margin_m = 0.02;
  // ... and sleeps again when the knife is away and the moving food's RMS speed stays under this
  // (m/s) for rest_duration_s.
  double rest_speed_m_s = 0.005;
  double rest_duration_s = 0.05;
  // With several foods, those the knife is away from sleep while it cuts another (food_step.cc);
  // false simulates them all (what tests compare against).
  bool objects_sleep = true;
  double initial_grid_nodes = 0.0;           // of the box around all foods at rest (scene_budget.h)
};

// The knife can touch the food's grid once it is within 1.5 cells of a particle (the quadratic
// B-spline stencil's reach); one cell more of slack. The check runs at both ends of every 2 ms
// physics step, so the knife's travel within a step needs no margin of its own. Waking sooner only
// integrates food at rest: 2 cm at dx 4 mm was a quarter of a second of MPM before a slow cut's
// first contact (docs/benchmarks/wake_margin.md).
inline constexpr double kActivationMarginCells = 2.5;

inline constexpr std::size_t kParticlesPerMpmThread = 5'000;  // fewer per thread: one thread is faster

// Builds the food model. Throws SceneError naming the field at fault (unknown food or material,
// bad override, an object off the table, too many particles or grid nodes (scene_budget.h, checked
// before sampling), an effect without effects.mpm).
FoodModel CompileFoodModel(const SceneConfig& config, const SceneLayout& layout);

}  // namespace culinarycut
