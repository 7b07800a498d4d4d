// The compiled, read-only description of a session (MuJoCo's mjModel): robot, furniture, timing.
// Shared by every State made from it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>
#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/render/camera.h"
#include "sim/robot/robot_description.h"
#include "sim/safety/limiter.h"
#include "sim/world/food_model.h"
#include "sim/world/scene_config.h"
#include "sim/core/scene_layout.h"
#include "sim/world/task_model.h"

namespace culinarycut {

// Names of the knife frames in the robot description (see docs/robot.md).
inline constexpr const char* kTcpFrame = "knife_tcp";
inline constexpr const char* kFlangeFrame = "panda_link8";

// A scene the engine cannot build; the message names the field at fault.
class SceneError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct Model {
  SceneConfig config;                   // fully resolved: every default filled in
  RobotDescription robot;
  SceneLayout layout;
  Eigen::Isometry3d robot_base_in_world;  // end-effector targets arrive in the world frame
  Eigen::Isometry3d tcp_in_last_link;   // knife TCP (middle of the cutting edge)
  Eigen::Isometry3d flange_in_last_link;
  double control_timestep_s = 0.05;
  double physics_timestep_s = 0.002;
  int substeps_per_control_step = 25;
  Eigen::VectorXd initial_qpos_rad;
  std::optional<FoodModel> food;        // only when the scene declares MPM food
  std::vector<render::CameraSpec> cameras;  // config.cameras resolved, in the same order; empty: no rendering
  std::optional<TaskModel> task;        // only when the scene declares a task (needs food with topology)
  std::optional<safety::LimiterModel> limiter;  // only with effects.safety_limiter (needs food)
  std::uint64_t fingerprint = 0;        // changes whenever anything that shapes a State changes
  std::size_t estimated_memory_bytes = 0;  // what a session of this model will hold (scene_budget.h)
};

// Compiles a config against a loaded robot. Throws SceneError with an actionable message. A scene
// with effects.safety_limiter needs `force_model` (the fitted force regression, see sim/safety).
std::shared_ptr<const Model> CompileModel(const SceneConfig& config, const RobotDescription& robot,
                                          std::shared_ptr<const safety::ForceModel> force_model = nullptr);

// An error naming `field` when q has the wrong size, a non-finite value or leaves the joint limits.
std::optional<std::string> CheckJointPositions(const RobotDescription& robot, const std::vector<double>& q_rad,
                                               const std::string& field);

// The Panda-with-knife description shipped in assets/ (path from CULINARYCUT_ASSETS_DIR or the build).
std::string DefaultRobotUrdfPath();

}  // namespace culinarycut
