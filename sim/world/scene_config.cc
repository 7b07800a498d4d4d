#include "sim/world/scene_config.h"

#include <cmath>
#include <sstream>

#include "sim/safety/limiter.h"

namespace culinarycut {

std::vector<double> ReadyPose() { return {0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4}; }

std::optional<std::string> ValidateSafetyConfig(const SafetyConfig& safety) {
  std::ostringstream error;
  if (!std::isfinite(safety.max_force_n) || safety.max_force_n <= 0) {
    error << "scene.safety.max_force_n must be a positive, finite force (N), got " << safety.max_force_n;
    return error.str();
  }
  if (!std::isfinite(safety.margin) || safety.margin < 0 || safety.margin > 0.9) {
    error << "scene.safety.margin must be in [0, 0.9], got " << safety.margin;
    return error.str();
  }
  if (!std::isfinite(safety.max_entry_angle_deg) || safety.max_entry_angle_deg <= 0 || safety.max_entry_angle_deg > 90) {
    error << "scene.safety.max_entry_angle_deg must be in (0, 90] degrees, got " << safety.max_entry_angle_deg;
    return error.str();
  }
  for (std::size_t i = 0; i < safety.guards.size(); ++i) {
    const std::string& guard = safety.guards[i];
    if (!safety::ParseGuard(guard)) {
      return "scene.safety.guards[" + std::to_string(i) + "] is \"" + guard +
             "\"; the guards are speed, force and entry_angle (empty: all)";
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (safety.guards[j] == guard) return "scene.safety.guards[" + std::to_string(i) + "] repeats \"" + guard + "\"";
    }
  }
  return std::nullopt;
}

std::optional<std::string> ValidateSceneConfig(const SceneConfig& config) {
  std::ostringstream error;
  const RobotConfig& robot = config.robot;
  // At least 1 Hz keeps one Step to at most 20000 physics substeps (a bounded call).
  if (!std::isfinite(robot.control_frequency_hz) || robot.control_frequency_hz < 1 || robot.control_frequency_hz > 1000) {
    error << "scene.robot.control_frequency_hz must be in [1, 1000] Hz, got " << robot.control_frequency_hz;
    return error.str();
  }
  const double ratio = robot.physics_frequency_hz / robot.control_frequency_hz;
  if (!std::isfinite(ratio) || ratio < 1 || std::abs(ratio - std::round(ratio)) > 1e-9 || robot.physics_frequency_hz > 20000) {
    error << "scene.robot.physics_frequency_hz (" << robot.physics_frequency_hz
          << " Hz) must be an integer multiple of control_frequency_hz (" << robot.control_frequency_hz
          << " Hz) and at most 20000 Hz";
    return error.str();
  }
  if (robot.physics_frequency_hz < 500) {
    error << "scene.robot.physics_frequency_hz must be at least 500 Hz for stable joint control, got "
          << robot.physics_frequency_hz;
    return error.str();
  }
  if (!std::isfinite(robot.joint_stiffness_per_s) || robot.joint_stiffness_per_s <= 0 ||
      robot.joint_stiffness_per_s > 0.5 * robot.physics_frequency_hz) {
    error << "scene.robot.joint_stiffness must be in (0, physics_frequency_hz / 2] 1/s, got "
          << robot.joint_stiffness_per_s;
    return error.str();
  }
  if (config.effects.safety_limiter) {
    if (const auto safety_error = ValidateSafetyConfig(config.safety)) return safety_error;
  }
  if (config.scene != "table" && config.scene != "kitchen") {
    return "scene.scene must be \"table\" or \"kitchen\", got \"" + config.scene + "\"";
  }
  if (config.quality == "accuracy_target" && !config.accuracy_target) {
    return "scene.quality \"accuracy_target\" needs scene.accuracy_target (it names the setting a target chose)";
  }
  if (config.quality != "draft" && config.quality != "standard" && config.quality != "fine" &&
      config.quality != "accuracy_target") {
    return "scene.quality must be \"draft\", \"standard\" or \"fine\", got \"" + config.quality + "\"";
  }
  return std::nullopt;
}

}  // namespace culinarycut
