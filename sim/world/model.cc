#include "sim/world/model.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "sim/core/assets.h"
#include "sim/world/camera_rig.h"
#include "sim/world/scene_budget.h"

namespace culinarycut {
namespace {

// FNV-1a over raw bytes: a stable fingerprint of what a snapshot depends on.
void HashBytes(std::uint64_t* hash, const void* data, size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    *hash ^= bytes[i];
    *hash *= 1099511628211ULL;
  }
}

// The limiter of a scene: it limits the knife against the food, so it needs food, and the force model.
safety::LimiterModel CompileLimiter(const SafetyConfig& config, const Model& model,
                                   std::shared_ptr<const safety::ForceModel> force_model) {
  if (!model.food) {
    throw SceneError("scene.effects.safety_limiter needs food (effects.mpm and scene.objects): it limits the knife "
                     "against the food");
  }
  if (!force_model) {
    throw SceneError("scene.effects.safety_limiter needs the safety force model, and none was loaded");
  }
  safety::LimiterModel limiter;
  limiter.force_model = std::move(force_model);
  limiter.settings.max_force_n = config.max_force_n;
  limiter.settings.margin = config.margin;
  limiter.settings.max_entry_angle_deg = config.max_entry_angle_deg;
  if (!config.guards.empty()) {
    limiter.settings.guards = {false, false, false};
    for (const std::string& name : config.guards) limiter.settings.guards[static_cast<int>(*safety::ParseGuard(name))] = true;
  }
  return limiter;
}

}  // namespace

std::string DefaultRobotUrdfPath() {
  return AssetsDir() + "/panda/panda_knife.urdf";
}

std::optional<std::string> CheckJointPositions(const RobotDescription& robot, const std::vector<double>& q_rad,
                                               const std::string& field) {
  std::ostringstream error;
  if (static_cast<int>(q_rad.size()) != robot.dof()) {
    error << field << " must have " << robot.dof() << " values, got " << q_rad.size();
    return error.str();
  }
  for (int i = 0; i < robot.dof(); ++i) {
    const JointLimits& limits = robot.limits[i];
    if (!std::isfinite(q_rad[i]) || q_rad[i] < limits.lower_rad || q_rad[i] > limits.upper_rad) {
      error << field << "[" << i << "] = " << q_rad[i] << " rad is outside the joint limits [" << limits.lower_rad
            << ", " << limits.upper_rad << "]";
      return error.str();
    }
  }
  return std::nullopt;
}

std::shared_ptr<const Model> CompileModel(const SceneConfig& config, const RobotDescription& robot,
                                          std::shared_ptr<const safety::ForceModel> force_model) {
  if (const auto error = ValidateSceneConfig(config)) throw SceneError(*error);
  auto model = std::make_shared<Model>();
  model->config = config;
  model->robot = robot;
  model->robot_base_in_world = Eigen::Isometry3d::Identity();
  model->robot_base_in_world.translation() = model->layout.robot_base_position_m;
  try {
    model->tcp_in_last_link = robot.TipFrame(kTcpFrame);
    model->flange_in_last_link = robot.TipFrame(kFlangeFrame);
  } catch (const std::out_of_range& error) {
    throw SceneError(std::string("the robot description lacks a frame the engine needs: ") + error.what());
  }
  model->control_timestep_s = 1.0 / config.robot.control_frequency_hz;
  model->substeps_per_control_step =
      static_cast<int>(std::lround(config.robot.physics_frequency_hz / config.robot.control_frequency_hz));
  model->physics_timestep_s = model->control_timestep_s / model->substeps_per_control_step;

  std::vector<double> initial = config.robot.initial_qpos_rad.empty() ? ReadyPose() : config.robot.initial_qpos_rad;
  model->config.robot.initial_qpos_rad = initial;
  model->initial_qpos_rad = Eigen::Map<const Eigen::VectorXd>(initial.data(), static_cast<long>(initial.size()));
  if (const auto error = CheckJointPositions(robot, initial, "scene.robot.initial_qpos")) throw SceneError(*error);

  // Cameras first: they are cheap to resolve, and a scene past the pixel budget must be refused
  // before its food is sampled.
  model->cameras = ResolveCameras(config.cameras, model->layout, robot);
  std::int64_t camera_pixels = 0;
  for (const render::CameraSpec& camera : model->cameras) camera_pixels += std::int64_t{camera.width} * camera.height;
  if (camera_pixels > kMaxCameraPixelsPerSession) {
    throw SceneError("scene.cameras: " + std::to_string(camera_pixels) + " pixels in all, more than the " +
                     std::to_string(kMaxCameraPixelsPerSession) +
                     " a session may render; lower width and height or declare fewer cameras");
  }
  for (std::size_t i = 0; i < model->cameras.size(); ++i) {  // echo what each camera resolved to
    const render::CameraSpec& camera = model->cameras[i];
    CameraConfig& resolved = model->config.cameras[i];
    resolved.pose = camera.pose_in_world;
    resolved.attached_link = camera.attached_link;
    resolved.fov_y_deg = camera.fov_y_deg;
    resolved.width = camera.width;
    resolved.height = camera.height;
    resolved.channels.clear();
    if (camera.rgb) resolved.channels.push_back("rgb");
    if (camera.depth) resolved.channels.push_back("depth");
    if (camera.segmentation) resolved.channels.push_back("segmentation");
    if (resolved.rgb_encoding.empty()) resolved.rgb_encoding = "raw";
  }

  const EffectsConfig& effects = config.effects;
  if (effects.mpm || !config.foods.empty() || effects.plasticity || effects.damage || effects.friction ||
      effects.topology || effects.force_sensing) {
    model->food = CompileFoodModel(config, model->layout);  // validates the effects against the foods
    const double mpm_substeps = model->substeps_per_control_step *
                                std::ceil(model->physics_timestep_s / mpm::StableTimestep(*model->food->solver));
    if (!(mpm_substeps <= kMaxMpmSubstepsPerControlStep)) {
      std::ostringstream message;
      message << "scene.mpm.cfl: the food needs about " << std::setprecision(3) << mpm_substeps
              << " MPM substeps per control step (limit " << std::setprecision(6) << kMaxMpmSubstepsPerControlStep
              << "); raise scene.mpm.cfl, use a coarser scene.quality or a softer material (youngs_modulus_pa)";
      throw SceneError(message.str());
    }
  }
  const std::size_t particles = model->food ? model->food->initial_particles.size() : 0;
  model->estimated_memory_bytes =
      EstimatedSessionBytes(particles, model->food ? model->food->initial_grid_nodes : 0.0, camera_pixels);

  if (!config.task.empty()) {
    if (!model->food) throw SceneError("scene.task needs food: declare scene.objects with effects.mpm");
    model->task = CompileTask(config.task, *model->food, config.seed);
    if (config.task.instruction.empty()) {  // echo the spec with the default rules applied
      const task::CutSpec& spec = model->task->spec;
      TaskConfig& resolved = model->config.task;
      resolved.cut_style = task::Name(spec.style);
      resolved.cut_state = task::Name(spec.state);
      resolved.ratio = spec.state == task::CutState::kRatio ? spec.ratio : 0.0;
      resolved.split_pieces = spec.state == task::CutState::kSplit ? spec.split_pieces : 0;
      resolved.target_object = spec.target_object;
      resolved.reference = task::Name(spec.reference);
    }
  }
  if (config.effects.safety_limiter) model->limiter = CompileLimiter(config.safety, *model, std::move(force_model));
  if (model->limiter) {  // echo the guards that run
    model->config.safety.guards.clear();
    for (int i = 0; i < safety::kGuardCount; ++i) {
      if (model->limiter->settings.guards[i]) model->config.safety.guards.push_back(safety::kGuardNames[i]);
    }
  }
  std::uint64_t hash = 1469598103934665603ULL;
  HashBytes(&hash, &model->control_timestep_s, sizeof(double));
  HashBytes(&hash, &model->substeps_per_control_step, sizeof(int));
  HashBytes(&hash, &config.robot.joint_stiffness_per_s, sizeof(double));
  HashBytes(&hash, robot.name.data(), robot.name.size());
  for (const auto& origin : robot.joint_origins) HashBytes(&hash, origin.data(), 16 * sizeof(double));
  for (const auto& link : robot.links) HashBytes(&hash, &link.mass_kg, sizeof(double));
  if (model->food) {
    const mpm::Particles<float>& particles = model->food->initial_particles;
    const std::uint64_t count = particles.size();
    HashBytes(&hash, &count, sizeof(count));
    for (int axis = 0; axis < 3; ++axis) HashBytes(&hash, particles.position[axis].data(), count * sizeof(float));
    HashBytes(&hash, &model->food->solver->config.dx_m, sizeof(double));
    HashBytes(&hash, &model->food->solver->config.cfl, sizeof(double));
    HashBytes(&hash, &model->food->solver->config.mass_scaling, sizeof(double));
    HashBytes(&hash, &model->food->solver->config.activity.radius_m, sizeof(double));
  }
  model->fingerprint = hash;
  return model;
}

}  // namespace culinarycut
