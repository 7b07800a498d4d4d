// The food part of a snapshot: every particle field, the solver's substep count (it decides when
// particles are reordered), the coupling left for the next physics step, pieces and bookkeeping.
#pragma once

#include <memory>

#include "sim/world/byte_stream.h"
#include "sim/world/food_model.h"
#include "sim/world/food_state.h"

namespace culinarycut {

void WriteFoodState(const FoodState& food, ByteWriter* writer);

// Throws SnapshotError for arrays of the wrong size or values no simulation produces.
std::unique_ptr<FoodState> ReadFoodState(const FoodModel& model, const SceneLayout& layout, ByteReader* reader);

}  // namespace culinarycut
