// Fuzz target: a StepRequest's action as bytes -> the wire's ActionFromWire -> one Step of a
// robot-only session. Bad actions are refused with the wire's or the engine's error types; an
// accepted one must step without a crash, a sanitizer report or a non-finite joint.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "server/wire/action.h"
#include "server/wire/field_error.h"
#include "sim/world/controller.h"
#include "sim/world/model.h"
#include "sim/world/state.h"
#include "sim/world/step.h"

using namespace culinarycut;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  static const std::shared_ptr<const Model> model = CompileModel(SceneConfig{}, robot);
  v1::StepRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return 0;
  State state;
  ResetState(*model, &state, 0, {});
  Action action;
  try {
    action = server::ActionFromWire(request.action());
  } catch (const server::FieldError&) {
    return 0;
  }
  if (ValidateAction(*model, action)) return 0;  // refused with the element named, as the server does
  Step(*model, &state, action);
  for (double q : state.physics->JointPositions()) {
    if (!std::isfinite(q)) __builtin_trap();
  }
  return 0;
}
