// One control step (MuJoCo's mj_step), as a short chain of named, timed stages:
//   apply action -> safety limiter (only with it on) -> per physics step (robot -> food)
//   -> end of food step -> task evaluation -> clock.
// Reward, success and termination are the engine's, so a C++ user of sim/world gets them too.
#pragma once

#include <functional>
#include <optional>

#include "sim/core/stage_timer.h"
#include "sim/robot/inverse_kinematics.h"
#include "sim/safety/limiter.h"
#include "sim/task/success_metrics.h"
#include "sim/world/controller.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

struct StepResult {
  // ManiSkill's sparse reward: 1 while the scene's task is done, else 0 (always 0 without a task).
  double reward = 0.0;
  bool success = false;      // the scene's task is done now
  bool terminated = false;   // the episode ended inside the task (success)
  bool truncated = false;    // max_episode_steps reached
  std::optional<task::TaskScore> task_score;  // only when the scene declares a task

  bool action_clipped = false;
  std::optional<IkResult> ik;     // end-effector modes only
  int substeps = 0;               // robot physics steps
  int mpm_substeps = 0;           // MPM substeps (0 while the food sleeps or without food)
  bool knife_contact = false;     // the knife touched the food during this step
  bool first_contact = false;     // ... for the first time this episode (the contact phase begins)
  // The knife was in the food and a joint of the arm at its effort limit for at least half of the
  // step's physics steps: the Panda pushes with all it has, and the food may be too hard to cut.
  bool knife_stalled = false;
  bool cancelled = false;         // the cancel check said stop: nothing of this step was applied
  std::optional<safety::LimiterReport> safety;  // only with effects.safety_limiter

  // Wall time of each stage (ms); never part of the simulation, so never compared for determinism.
  StageTimes timings;
  double wall_time_ms = 0.0;      // the whole step
};

// Asked between physics substeps and between MPM substeps; returning true stops the step.
using CancelCheck = std::function<bool()>;

// Asked before each physics step: the most threads the food's MPM may use now (0: its model's).
using ThreadLimit = std::function<int()>;

// Preconditions: state has been reset and ValidateAction(model, action) found nothing.
// With a cancel check, a step it stops leaves the state exactly as before the call
// (StepResult::cancelled; what it would put back is saved as the step goes, step_rollback.h, which
// only cancellable steps pay for: the robot always, the food's particles only if the step moves them).
// Throws std::runtime_error when the food's MPM state runs away (NaN positions, a grid blown up);
// the state is then half-stepped and must be reset or restored before it is stepped again.
// `thread_limit` shares the machine with other work; it never changes what is simulated.
StepResult Step(const Model& model, State* state, const Action& action, const CancelCheck& cancelled = {},
                const ThreadLimit& thread_limit = {});

}  // namespace culinarycut
