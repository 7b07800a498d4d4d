#include "sim/world/step_rollback.h"

#include "sim/world/snapshot.h"

namespace culinarycut {

StepRollback::StepRollback(const Model& model, const State& state)
    : model_(model), rest_(SaveStateButFoodBody(model, state)) {}

void StepRollback::BeforeFoodBodyChanges(const FoodState& food) {
  if (!food_body_) food_body_ = SaveFoodBody(model_, food);
}

void StepRollback::Restore(State* state) const {
  RestoreSavedParts(model_, rest_, food_body_ ? &*food_body_ : nullptr, state);
}

}  // namespace culinarycut
