// What Step needs to put the state back when it is cancelled half-way, saved as late as it can be:
// the robot and the food's scalars at the start of the step (a few hundred bytes), the food's body
// (its particles, cuts and pieces) only just before the step first changes it. A step in which the
// food sleeps copies no particle; one in which it is awake copies it once, as before.
#pragma once

#include <optional>
#include <string>

#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

class StepRollback {
 public:
  // Saves all of `state` but its food's body.
  StepRollback(const Model& model, const State& state);

  // Call before anything changes the food's body: the first call saves it, later calls do nothing.
  void BeforeFoodBodyChanges(const FoodState& food);

  // Puts the state back as it was when this was made.
  void Restore(State* state) const;

  std::size_t saved_bytes() const { return rest_.size() + (food_body_ ? food_body_->size() : 0); }

 private:
  const Model& model_;
  std::string rest_;
  std::optional<std::string> food_body_;
};

}  // namespace culinarycut
