// Stage "safety" of Step (scenes with effects.safety_limiter): after the action has become a joint
// target and before the robot's controller tracks it, the limiter (sim/safety) shortens the
// joint-space step q_target - q until the knife's motion into the food fits the guards' caps. Scaling
// the joint step works for every control mode alike; the step keeps its direction (docs/safety.md).
#pragma once

#include "sim/safety/limiter.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

// Under this much motion into the food per control step (m) counts as none (a held knife's FK noise).
inline constexpr double kHoldToleranceM = 1e-4;

// Precondition: model.limiter and model.food are set; state->q_target_rad is the action's target.
// Shortens state->q_target_rad when a guard binds and adds the step's interventions and assessment
// to state->safety.
safety::LimiterReport LimitJointTarget(const Model& model, State* state);

}  // namespace culinarycut
