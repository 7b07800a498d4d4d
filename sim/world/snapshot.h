// A session's State as bytes, to branch and replay episodes. A snapshot restores only into a
// session whose Model has the same fingerprint, and replays the following steps bit for bit.
// The fields and their order come from state_fields.h.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

class SnapshotError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Precondition: state has been reset.
std::string SaveSnapshot(const Model& model, const State& state);

// Throws SnapshotError (and leaves the state untouched) on corrupt or foreign bytes.
void RestoreSnapshot(const Model& model, const std::string& bytes, State* state);

// `to` becomes an independent copy of `from` (a reset state of the same model).
void CopyState(const Model& model, const State& from, State* to);

// A state in two parts, for Step's rollback (step_rollback.h): all of it but the food's body (the robot
// and a few scalars), and the food's body alone (particles, cuts, pieces). Bytes for this build only.
std::string SaveStateButFoodBody(const Model& model, const State& state);
std::string SaveFoodBody(const Model& model, const FoodState& food);
// Puts back what the parts saved; with no `food_body`, the state keeps its current food body. The
// bytes come from the functions above on this model (not checked as a restored snapshot is).
void RestoreSavedParts(const Model& model, const std::string& state_but_food_body, const std::string* food_body,
                       State* state);

// The name of the first field in which two reset states of one model differ, or nothing when
// they are equal bit for bit (what determinism tests compare).
std::optional<std::string> FirstStateDifference(const Model& model, const State& a, const State& b);

}  // namespace culinarycut
