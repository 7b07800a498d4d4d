// What a client asks for, as a plain config struct with defaults (the wire's SceneSpec, minus the wire).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace culinarycut {

struct RobotConfig {
  double control_frequency_hz = 20.0;     // [1, 1000] Hz
  double physics_frequency_hz = 500.0;     // an integer multiple of control_frequency_hz
  std::vector<double> initial_qpos_rad;    // empty: the knife-down ready pose
  double joint_stiffness_per_s = 20.0;     // PD position gain (1/s): commanded qdot = k (q_target - q)
};

struct SceneConfig {
  std::uint64_t seed = 0;
  RobotConfig robot;
  std::string scene = "table";
  std::string quality = "standard";        // MPM accuracy preset: draft, standard, fine (no effect without food)
  std::uint32_t max_episode_steps = 0;     // 0: never truncate
};

// The knife-down "ready" pose (rad) used when initial_qpos is empty.
std::vector<double> ReadyPose();

// An error message naming the offending field, or nothing when the config is valid.
// (Joint positions are checked against the robot by CheckJointPositions in model.h.)
std::optional<std::string> ValidateSceneConfig(const SceneConfig& config);

}  // namespace culinarycut
