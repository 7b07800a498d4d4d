// One physics step of the food: while the knife is near or the food still moves, MPM substeps at
// the CFL time step (of sound, the knife's and the fastest particle's speed) with the knife collider following the robot's TCP from its pose at the start
// of the step to its pose at the end; the blade and handle impulses give the wrench on the knife.
#pragma once

#include <functional>

#include <Eigen/Geometry>

#include "sim/world/food_model.h"
#include "sim/world/food_state.h"

namespace culinarycut {

struct FoodStepReport {
  int substeps = 0;        // MPM substeps run (0 while asleep)
  bool contact = false;    // the knife touched the food during the step
  double max_c_hat = 0.0;  // largest contact strength of the substeps
  bool cancelled = false;  // the cancel check stopped the step between substeps (state half-stepped)
};

// Advances the food by `duration_s` (one physics step). The wrench and the speed resistance are
// left in `state` for the robot's next physics step. `cancelled`, when given, is asked between
// MPM substeps; if it says stop, the food is left half-stepped and the report says so.
// `before_body_changes`, when given, is called before the food's body (particles, cuts) first changes.
FoodStepReport AdvanceFood(const FoodModel& model, const Eigen::Isometry3d& tcp_start,
                           const Eigen::Isometry3d& tcp_end, double duration_s, FoodState* state,
                           const std::function<bool()>& cancelled = {},
                           const std::function<void()>& before_body_changes = {});

}  // namespace culinarycut
