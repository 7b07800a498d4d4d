// Fuzz target: a SceneSpec as bytes -> the wire's SceneFromWire -> the engine's CompileModel. Bad
// scenes must be refused with the engine's or the wire's error types; anything else (another
// exception, a crash, a sanitizer report) is a finding. The resolution is pinned to a coarse grid
// and small foods so each input takes milliseconds; the budgets have tests of their own.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "server/wire/field_error.h"
#include "server/wire/scene.h"
#include "sim/task/cut_spec.h"
#include "sim/world/model.h"

using namespace culinarycut;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  v1::SceneSpec wire;
  if (!wire.ParseFromArray(data, static_cast<int>(size))) return 0;
  try {
    SceneConfig config = server::SceneFromWire(wire);
    config.quality = "draft";
    config.mpm = MpmResolutionConfig{};
    for (FoodConfig& food : config.foods) food.scale = std::min(food.scale, 1.5);
    CompileModel(config, robot);
  } catch (const server::FieldError&) {
  } catch (const server::UnimplementedField&) {
  } catch (const SceneError&) {
  } catch (const task::TaskError&) {
  }
  return 0;
}
