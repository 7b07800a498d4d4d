#include "server/wire/scene.h"

#include <limits>

#include "server/wire/camera.h"
#include "server/wire/values.h"
#include "sim/mpm/solver_config.h"
#include "sim/world/measured_accuracy.h"
#include "sim/world/quality_preset.h"

namespace culinarycut::server {
namespace {

FoodConfig FoodFromWire(const v1::FoodObject& wire, const std::string& field) {
  FoodConfig food;
  food.food = TextFromWire(wire.food(), field + ".food");
  if (food.food.empty()) throw FieldError(field + ".food", "is empty; name a food, e.g. \"cucumber\"");
  food.scale = wire.scale() == 0 ? 1.0 : RangeFromWire(wire.scale(), 1e-3, 10.0, field + ".scale");
  const v1::Pose& pose = wire.pose();
  if (pose.position_size() == 2) {  // [x, y]: resting on the board there
    food.board_xy_m = Eigen::Vector2d(FiniteFromWire(pose.position(0), field + ".pose.position[0]"),
                                      FiniteFromWire(pose.position(1), field + ".pose.position[1]"));
  } else if (pose.position_size() != 0) {
    if (pose.position_size() != 3) {
      throw FieldError(field + ".pose.position", "must have 3 values [x, y, z], 2 [x, y] (resting on the board) or none");
    }
    food.position_m = Vector3FromWire(pose.position(), field + ".pose.position");
  }
  if (pose.quaternion_size() != 0) {
    if (pose.quaternion_size() != 4) {
      throw FieldError(field + ".pose.quaternion", "must have 4 values [w, x, y, z] or none");
    }
    const Eigen::Quaterniond q(pose.quaternion(0), pose.quaternion(1), pose.quaternion(2), pose.quaternion(3));
    if (!q.coeffs().allFinite() || q.norm() < 1e-6) {
      throw FieldError(field + ".pose.quaternion", "must be finite and non-zero");
    }
    food.orientation = q.normalized();
  }
  food.material = TextFromWire(wire.material(), field + ".material");
  for (const auto& [key, value] : wire.material_overrides()) {
    const std::string& name = TextFromWire(key, field + ".material_overrides (a key)", 64);
    food.material_overrides[name] = FiniteFromWire(value, field + ".material_overrides." + name);
  }
  return food;
}

TaskConfig TaskFromWire(const v1::TaskSpec& task) {
  return TaskConfig{TextFromWire(task.instruction(), "scene.task.instruction", 2000),
                    TextFromWire(task.cut_style(), "scene.task.cut_style"),
                    TextFromWire(task.cut_state(), "scene.task.cut_state"),
                    FiniteFromWire(task.ratio(), "scene.task.ratio"),
                    CountFromWire(task.split_pieces(), 1000, "scene.task.split_pieces"),
                    TextFromWire(task.target_object(), "scene.task.target_object"),
                    TextFromWire(task.reference(), "scene.task.reference")};
}

// 0 / unset keeps each default; the engine checks the ranges (ValidateSafetyConfig).
SafetyConfig SafetyFromWire(const v1::SafetySpec& wire) {
  SafetyConfig safety;
  if (wire.max_force_n() != 0) safety.max_force_n = FiniteFromWire(wire.max_force_n(), "scene.safety.max_force_n");
  if (wire.has_margin()) safety.margin = FiniteFromWire(wire.margin().value(), "scene.safety.margin");
  if (wire.max_entry_angle_deg() != 0) {
    safety.max_entry_angle_deg = FiniteFromWire(wire.max_entry_angle_deg(), "scene.safety.max_entry_angle_deg");
  }
  for (int i = 0; i < wire.guards_size(); ++i) {
    safety.guards.push_back(TextFromWire(wire.guards(i), "scene.safety.guards[" + std::to_string(i) + "]"));
  }
  return safety;
}

AccuracyTargetConfig AccuracyTargetFromWire(const v1::AccuracyTarget& wire) {
  AccuracyTargetConfig target;
  if (wire.force_error() != 0) target.force_error = FiniteFromWire(wire.force_error(), "scene.accuracy_target.force_error");
  if (wire.force_curve_error() != 0) {
    target.force_curve_error = FiniteFromWire(wire.force_curve_error(), "scene.accuracy_target.force_curve_error");
  }
  if (wire.cut_position_error_mm() != 0) {
    target.cut_position_error_mm =
        FiniteFromWire(wire.cut_position_error_mm(), "scene.accuracy_target.cut_position_error_mm");
  }
  return target;
}

}  // namespace

void MpmResolutionToWire(const MpmResolution& resolution, v1::MpmSettings* wire) {
  wire->set_dx(resolution.dx_m);
  wire->set_particles_per_cell(static_cast<std::uint32_t>(resolution.particles_per_cell));
  wire->set_cfl(resolution.cfl);
  wire->set_mass_scaling(resolution.mass_scaling);
  wire->set_activity_radius(resolution.activity_radius_m);
}

void ExpectedAccuracyToWire(const MpmResolution& resolution, v1::ExpectedAccuracy* wire) {
  wire->set_setting(SettingLabel(resolution));
  wire->set_study(AccuracyStudyName());
  const std::optional<MeasuredAccuracy> measured = FindMeasuredAccuracy(resolution);
  wire->set_measured(measured.has_value());
  if (!measured) {
    // Not a zero error at zero cost: no number at all (NaN, "NaN" in JSON), which no comparison picks.
    const double unmeasured = std::numeric_limits<double>::quiet_NaN();
    for (auto set : {&v1::ExpectedAccuracy::set_force_error, &v1::ExpectedAccuracy::set_mean_force_error,
                     &v1::ExpectedAccuracy::set_force_curve_error, &v1::ExpectedAccuracy::set_cut_position_error_mm,
                     &v1::ExpectedAccuracy::set_relative_cost}) {
      (wire->*set)(unmeasured);
    }
    return;
  }
  wire->set_force_error(measured->peak_force_error);
  wire->set_mean_force_error(measured->mean_force_error);
  wire->set_force_curve_error(measured->force_curve_error);
  wire->set_cut_position_error_mm(measured->cut_position_error_mm);
  wire->set_relative_cost(measured->relative_cost);
}

void ResolutionCatalogueToWire(v1::ServerInfo* info) {
  info->mutable_limits()->set_max_mass_scaling(mpm::kMaxMassScaling);
  info->mutable_limits()->set_min_activity_radius_cells(mpm::kMinActivityRadiusCells);
  for (const std::string& name : QualityPresetNames()) {
    const MpmResolution resolution = ResolveMpmResolution(name, std::nullopt, {});
    v1::QualityPreset* preset = info->add_quality_presets();
    preset->set_name(name);
    MpmResolutionToWire(resolution, preset->mutable_mpm());
    ExpectedAccuracyToWire(resolution, preset->mutable_expected());
  }
}

SceneConfig SceneFromWire(const v1::SceneSpec& wire) {
  const v1::Effects& effects = wire.effects();
  SceneConfig config;
  config.effects = EffectsConfig{effects.mpm(),      effects.plasticity(),    effects.damage(),        effects.friction(),
                                 effects.topology(), effects.force_sensing(), effects.safety_limiter()};
  if (wire.has_safety()) {
    if (!effects.safety_limiter()) throw FieldError("scene.safety", "is set but effects.safety_limiter is off; turn it on or drop scene.safety");
    config.safety = SafetyFromWire(wire.safety());
  }
  for (int i = 0; i < wire.objects_size(); ++i) {
    config.foods.push_back(FoodFromWire(wire.objects(i), "scene.objects[" + std::to_string(i) + "]"));
  }
  for (int i = 0; i < wire.cameras_size(); ++i) {
    config.cameras.push_back(CameraFromWire(wire.cameras(i), "scene.cameras[" + std::to_string(i) + "]"));
  }
  config.task = TaskFromWire(wire.task());
  const v1::MpmSettings& mpm = wire.mpm();
  if (mpm.dx() != 0) config.mpm.dx_m = FiniteFromWire(mpm.dx(), "scene.mpm.dx");
  if (mpm.particles_per_cell() != 0) {
    config.mpm.particles_per_cell = CountFromWire(mpm.particles_per_cell(), 1000, "scene.mpm.particles_per_cell");
  }
  if (mpm.cfl() != 0) config.mpm.cfl = FiniteFromWire(mpm.cfl(), "scene.mpm.cfl");
  if (mpm.mass_scaling() != 0) config.mpm.mass_scaling = FiniteFromWire(mpm.mass_scaling(), "scene.mpm.mass_scaling");
  if (mpm.activity_radius() != 0) {
    config.mpm.activity_radius_m = FiniteFromWire(mpm.activity_radius(), "scene.mpm.activity_radius");
  }
  config.seed = wire.seed();
  if (!wire.quality().empty()) config.quality = TextFromWire(wire.quality(), "scene.quality");
  if (wire.has_accuracy_target()) config.accuracy_target = AccuracyTargetFromWire(wire.accuracy_target());
  config.max_episode_steps = wire.max_episode_steps();
  if (!wire.scene().empty()) config.scene = TextFromWire(wire.scene(), "scene.scene");
  const v1::RobotSpec& robot = wire.robot();
  if (robot.control_frequency_hz() != 0) {
    config.robot.control_frequency_hz = FiniteFromWire(robot.control_frequency_hz(), "scene.robot.control_frequency_hz");
  }
  if (robot.physics_frequency_hz() != 0) {
    config.robot.physics_frequency_hz = FiniteFromWire(robot.physics_frequency_hz(), "scene.robot.physics_frequency_hz");
  }
  if (robot.joint_stiffness() != 0) {
    config.robot.joint_stiffness_per_s = FiniteFromWire(robot.joint_stiffness(), "scene.robot.joint_stiffness");
  }
  for (int i = 0; i < robot.initial_qpos_size(); ++i) {
    config.robot.initial_qpos_rad.push_back(
        FiniteFromWire(robot.initial_qpos(i), "scene.robot.initial_qpos[" + std::to_string(i) + "]"));
  }
  return config;
}

v1::SceneSpec SceneToWire(const SceneConfig& config) {
  v1::SceneSpec wire;
  wire.set_seed(config.seed);
  wire.set_scene(config.scene);
  wire.set_quality(config.quality);
  if (config.accuracy_target) {
    v1::AccuracyTarget* target = wire.mutable_accuracy_target();
    target->set_force_error(config.accuracy_target->force_error.value_or(0.0));
    target->set_force_curve_error(config.accuracy_target->force_curve_error.value_or(0.0));
    target->set_cut_position_error_mm(config.accuracy_target->cut_position_error_mm.value_or(0.0));
  }
  wire.set_max_episode_steps(config.max_episode_steps);
  v1::RobotSpec* robot = wire.mutable_robot();
  robot->set_control_frequency_hz(config.robot.control_frequency_hz);
  robot->set_physics_frequency_hz(config.robot.physics_frequency_hz);
  robot->set_joint_stiffness(config.robot.joint_stiffness_per_s);
  for (double q : config.robot.initial_qpos_rad) robot->add_initial_qpos(q);
  v1::Effects* effects = wire.mutable_effects();
  effects->set_mpm(config.effects.mpm);
  effects->set_plasticity(config.effects.plasticity);
  effects->set_damage(config.effects.damage);
  effects->set_friction(config.effects.friction);
  effects->set_topology(config.effects.topology);
  effects->set_force_sensing(config.effects.force_sensing);
  effects->set_safety_limiter(config.effects.safety_limiter);
  if (config.effects.safety_limiter) {
    v1::SafetySpec* safety = wire.mutable_safety();
    safety->set_max_force_n(config.safety.max_force_n);
    safety->mutable_margin()->set_value(config.safety.margin);
    for (const std::string& guard : config.safety.guards) safety->add_guards(guard);
    safety->set_max_entry_angle_deg(config.safety.max_entry_angle_deg);
  }
  for (const CameraConfig& camera : config.cameras) CameraToWire(camera, wire.add_cameras());
  if (!config.task.empty()) {
    v1::TaskSpec* task = wire.mutable_task();
    task->set_instruction(config.task.instruction);
    task->set_cut_style(config.task.cut_style);
    task->set_cut_state(config.task.cut_state);
    task->set_ratio(config.task.ratio);
    task->set_split_pieces(static_cast<std::uint32_t>(config.task.split_pieces));
    task->set_target_object(config.task.target_object);
    task->set_reference(config.task.reference);
  }
  for (const FoodConfig& food : config.foods) {
    v1::FoodObject* object = wire.add_objects();
    object->set_food(food.food);
    object->set_scale(food.scale);
    object->set_material(food.material);
    for (const auto& [key, value] : food.material_overrides) (*object->mutable_material_overrides())[key] = value;
    if (food.position_m) AssignVector(*food.position_m, object->mutable_pose()->mutable_position());
    if (food.board_xy_m) {
      object->mutable_pose()->add_position(food.board_xy_m->x());
      object->mutable_pose()->add_position(food.board_xy_m->y());
    }
    if (food.orientation) {
      for (double c : {food.orientation->w(), food.orientation->x(), food.orientation->y(), food.orientation->z()}) {
        object->mutable_pose()->add_quaternion(c);
      }
    }
  }
  return wire;
}

void ResolvedFoodToWire(const FoodModel& food, v1::SceneSpec* wire) {
  // An accuracy target chose the setting: the resolved quality names it (a preset, or "accuracy_target").
  if (wire->has_accuracy_target()) wire->set_quality(QualityNameOf(food.resolution));
  MpmResolutionToWire(food.resolution, wire->mutable_mpm());
  ExpectedAccuracyToWire(food.resolution, wire->mutable_expected_accuracy());
  for (int i = 0; i < wire->objects_size() && i < static_cast<int>(food.objects.size()); ++i) {
    PoseToWire(food.objects[i].pose, wire->mutable_objects(i)->mutable_pose());
    if (food.solver->materials[i].name != wire->objects(i).material() && wire->objects(i).material().empty()) {
      wire->mutable_objects(i)->set_material(food.solver->materials[i].name);
    }
  }
}

}  // namespace culinarycut::server
