// A session's State as bytes, to branch and replay episodes. A snapshot restores only into a
// session whose Model has the same fingerprint, and replays the following steps bit for bit.
#pragma once

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

}  // namespace culinarycut
