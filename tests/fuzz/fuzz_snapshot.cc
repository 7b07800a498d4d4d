// Fuzz target: snapshot bytes -> RestoreSnapshot, behind the server's HMAC seal (what a client that
// holds the key could send). A refused blob must leave the state as it was; an accepted one must
// step without a crash or a sanitizer report (an engine exception is fine: the server turns it into
// a broken session).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "sim/world/controller.h"
#include "sim/world/model.h"
#include "sim/world/snapshot.h"
#include "sim/world/state.h"
#include "sim/world/step.h"

using namespace culinarycut;

namespace {

// A draft cucumber with a task: every part of the State is in its snapshots.
SceneConfig CuttingScene() {
  SceneConfig config;
  config.quality = "draft";
  config.effects = EffectsConfig{true, true, true, true, true, true};
  FoodConfig cucumber;
  cucumber.food = "cucumber";
  cucumber.material_overrides["youngs_modulus_pa"] = 2e5;
  config.foods.push_back(cucumber);
  config.task.cut_state = "middle";
  return config;
}

const RobotDescription& Robot() {
  static const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  return robot;
}

const Model& CuttingModel() {
  static const std::shared_ptr<const Model> model = CompileModel(CuttingScene(), Robot());
  return *model;
}

}  // namespace

// With CULINARYCUT_FUZZ_WRITE_SEEDS=DIR: writes the corpus seeds (a fresh episode's snapshot, and one
// with the knife in the food after a descent) into DIR.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* folder = std::getenv("CULINARYCUT_FUZZ_WRITE_SEEDS");
  if (!folder) return 0;
  const Model& model = CuttingModel();
  State state;
  ResetState(model, &state, 0, {});
  std::ofstream(std::string(folder) + "/reset.snap", std::ios::binary) << SaveSnapshot(model, state);
  for (int i = 0; i < 40; ++i) {
    Step(model, &state, Action{ControlMode::kEndEffectorDeltaPosition, Eigen::Vector3d(0.0, 0.0, -0.1)});
  }
  std::ofstream(std::string(folder) + "/cutting.snap", std::ios::binary) << SaveSnapshot(model, state);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Model* model = &CuttingModel();
  static const State initial = [model] {
    State state;
    ResetState(*model, &state, 0, {});
    return state;
  }();
  State state;
  CopyState(*model, initial, &state);
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    RestoreSnapshot(*model, bytes, &state);
  } catch (const SnapshotError&) {
    if (FirstStateDifference(*model, initial, state)) __builtin_trap();  // a refused blob changed the state
    return 0;
  }
  try {
    Step(*model, &state, Action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)});
  } catch (const std::exception&) {
  }
  return 0;
}
