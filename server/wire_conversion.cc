#include "server/wire_conversion.h"

#include "server/camera_wire_conversion.h"
#include "server/task_wire_conversion.h"
#include "sim/world/control_mode.h"

namespace culinarycut::server {
namespace {

grpc::Status Unimplemented(const std::string& field, const std::string& what) {
  return grpc::Status(grpc::StatusCode::UNIMPLEMENTED,
                      field + ": " + what + " is not available in this server yet; GetServerInfo lists its capabilities");
}

// Copies an Eigen vector into a repeated double field.
template <typename Vector>
void AssignVector(const Vector& values, google::protobuf::RepeatedField<double>* field) {
  field->Assign(values.data(), values.data() + values.size());
}

// An unbounded float64 vector observation (empty low/high on the wire means unbounded).
v1::ArraySpec* AddArraySpec(v1::CreateSessionResponse* response, const std::string& name, int size,
                            const std::string& description) {
  v1::ArraySpec* spec = response->add_observation_spec();
  spec->set_name(name);
  spec->add_shape(size);
  spec->set_dtype("float64");
  spec->set_description(description);
  return spec;
}

grpc::Status InvalidField(const std::string& message) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message);
}

grpc::Status FoodFromWire(const v1::FoodObject& wire, const std::string& field, FoodConfig* food) {
  food->food = wire.food();
  if (food->food.empty()) return InvalidField(field + ".food is empty; name a food, e.g. \"cucumber\"");
  food->scale = wire.scale() == 0 ? 1.0 : wire.scale();
  if (!(food->scale > 0.0 && food->scale <= 10.0)) return InvalidField(field + ".scale must be in (0, 10]");
  const v1::Pose& pose = wire.pose();
  if (pose.position_size() != 0) {
    if (pose.position_size() != 3) return InvalidField(field + ".pose.position must have 3 values (m) or none");
    food->position_m = Eigen::Vector3d(pose.position(0), pose.position(1), pose.position(2));
    if (!food->position_m->allFinite()) return InvalidField(field + ".pose.position must be finite");
  }
  if (pose.quaternion_size() != 0) {
    if (pose.quaternion_size() != 4) return InvalidField(field + ".pose.quaternion must have 4 values [w, x, y, z] or none");
    const Eigen::Quaterniond q(pose.quaternion(0), pose.quaternion(1), pose.quaternion(2), pose.quaternion(3));
    if (!q.coeffs().allFinite() || q.norm() < 1e-6) return InvalidField(field + ".pose.quaternion must be finite and non-zero");
    food->orientation = q.normalized();
  }
  food->material = wire.material();
  for (const auto& [key, value] : wire.material_overrides()) food->material_overrides[key] = value;
  return grpc::Status::OK;
}

}  // namespace

grpc::Status SceneFromWire(const v1::SceneSpec& wire, SceneConfig* config) {
  const v1::Effects& effects = wire.effects();
  if (effects.safety_limiter()) return Unimplemented("scene.effects.safety_limiter", "the safety limiter");

  SceneConfig parsed;
  parsed.effects = EffectsConfig{effects.mpm(), effects.plasticity(), effects.damage(),
                                 effects.friction(), effects.topology(), effects.force_sensing()};
  for (int i = 0; i < wire.objects_size(); ++i) {
    if (grpc::Status status = FoodFromWire(wire.objects(i), "scene.objects[" + std::to_string(i) + "]", &parsed.foods.emplace_back());
        !status.ok()) {
      return status;
    }
  }
  for (int i = 0; i < wire.cameras_size(); ++i) {
    if (grpc::Status status = CameraFromWire(wire.cameras(i), "scene.cameras[" + std::to_string(i) + "]",
                                             &parsed.cameras.emplace_back());
        !status.ok()) {
      return status;
    }
  }
  const v1::TaskSpec& task = wire.task();
  parsed.task = TaskConfig{task.instruction(), task.cut_style(), task.cut_state(), task.ratio(),
                           static_cast<int>(std::min<std::uint32_t>(task.split_pieces(), 1000)), task.target_object(),
                           task.reference()};
  const v1::MpmSettings& mpm = wire.mpm();
  if (mpm.dx() != 0) parsed.mpm.dx_m = mpm.dx();
  if (mpm.particles_per_cell() != 0) parsed.mpm.particles_per_cell = static_cast<int>(std::min<std::uint32_t>(mpm.particles_per_cell(), 1000));
  if (mpm.cfl() != 0) parsed.mpm.cfl = mpm.cfl();
  parsed.seed = wire.seed();
  if (!wire.quality().empty()) parsed.quality = wire.quality();
  parsed.max_episode_steps = wire.max_episode_steps();
  if (!wire.scene().empty()) parsed.scene = wire.scene();
  const v1::RobotSpec& robot = wire.robot();
  if (robot.control_frequency_hz() != 0) parsed.robot.control_frequency_hz = robot.control_frequency_hz();
  if (robot.physics_frequency_hz() != 0) parsed.robot.physics_frequency_hz = robot.physics_frequency_hz();
  if (robot.joint_stiffness() != 0) parsed.robot.joint_stiffness_per_s = robot.joint_stiffness();
  parsed.robot.initial_qpos_rad.assign(robot.initial_qpos().begin(), robot.initial_qpos().end());
  *config = parsed;
  return grpc::Status::OK;
}

v1::SceneSpec SceneToWire(const SceneConfig& config) {
  v1::SceneSpec wire;
  wire.set_seed(config.seed);
  wire.set_scene(config.scene);
  wire.set_quality(config.quality);
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
    if (food.orientation) {
      for (double c : {food.orientation->w(), food.orientation->x(), food.orientation->y(), food.orientation->z()}) {
        object->mutable_pose()->add_quaternion(c);
      }
    }
  }
  return wire;
}

void ObservationToWire(const RobotObservation& observation, v1::Observation* wire) {
  v1::AgentObservation* agent = wire->mutable_agent();
  AssignVector(observation.qpos_rad, agent->mutable_qpos());
  AssignVector(observation.qvel_rad_s, agent->mutable_qvel());
  AssignVector(observation.qpos_target_rad, agent->mutable_qpos_target());
  AssignVector(observation.tcp_pose, wire->mutable_tcp_pose());
  AssignVector(observation.tcp_velocity, wire->mutable_tcp_velocity());
  AssignVector(observation.flange_pose, wire->mutable_flange_pose());
  AssignVector(observation.wrist_wrench, wire->mutable_wrist_wrench());
}

void ResolvedFoodToWire(const FoodModel& food, v1::SceneSpec* wire) {
  wire->mutable_mpm()->set_dx(food.resolution.dx_m);
  wire->mutable_mpm()->set_particles_per_cell(static_cast<std::uint32_t>(food.resolution.particles_per_cell));
  wire->mutable_mpm()->set_cfl(food.resolution.cfl);
  for (int i = 0; i < wire->objects_size() && i < static_cast<int>(food.objects.size()); ++i) {
    PoseToWire(food.objects[i].pose, wire->mutable_objects(i)->mutable_pose());
    if (food.materials[i].name != wire->objects(i).material() && wire->objects(i).material().empty()) {
      wire->mutable_objects(i)->set_material(food.materials[i].name);
    }
  }
}

void FoodObservationToWire(const State& state, v1::Observation* wire) {
  if (!state.food) return;
  v1::FoodObservation* food = wire->mutable_food();
  food->set_knife_contact(state.food->contact_last_step);
  food->set_mpm_awake(state.food->substeps_last_step > 0);
  for (const mpm::Piece& piece : state.food->pieces) {
    v1::FoodPiece* out = food->add_pieces();
    out->set_object(piece.object);
    out->set_particles(static_cast<std::uint32_t>(piece.particle_count));
    out->set_volume(piece.volume_m3);
    AssignVector(piece.centroid_m, out->mutable_centroid());
    AssignVector(piece.bounds_m.min(), out->mutable_bounds_min());
    AssignVector(piece.bounds_m.max(), out->mutable_bounds_max());
  }
}

void SessionStatsToWire(const Model& model, const State& state, v1::SessionStats* wire) {
  StampToWire(state.frame_id, state.sim_time_s, wire->mutable_stamp());
  wire->set_mpm_allocated(state.food != nullptr && state.food->solver != nullptr);
  if (model.food) {
    wire->set_mpm_dx(model.food->resolution.dx_m);
    wire->set_mpm_particles_per_cell(model.food->resolution.particles_per_cell);
    wire->set_mpm_cfl(model.food->resolution.cfl);
  }
  if (state.food && state.food->solver) {
    wire->set_mpm_particles(state.food->solver->particles().size());
    wire->set_mpm_substeps(state.food->substeps);
    wire->set_has_contact(state.food->first_contact_frame.has_value());
    wire->set_first_contact_frame(state.food->first_contact_frame.value_or(0));
  }
  const char* names[] = {"control", "physics", "mpm", "topology", "render"};
  static_assert(sizeof(names) / sizeof(names[0]) == static_cast<int>(Stage::kCount), "one name per stage");
  for (int stage = 0; stage < static_cast<int>(Stage::kCount); ++stage) {
    (*wire->mutable_stage_wall_time_s())[names[stage]] = state.timers.total_seconds[stage];
    (*wire->mutable_stage_calls())[names[stage]] = state.timers.calls[stage];
  }
}

v1::TelemetryFrame TelemetryToWire(const std::string& session_id, const RobotObservation& observation) {
  v1::TelemetryFrame frame;
  frame.set_session_id(session_id);
  StampToWire(observation.frame_id, observation.sim_time_s, frame.mutable_stamp());
  AssignVector(observation.qpos_rad, frame.mutable_qpos());
  AssignVector(observation.qvel_rad_s, frame.mutable_qvel());
  AssignVector(observation.tcp_pose, frame.mutable_tcp_pose());
  AssignVector(observation.wrist_wrench, frame.mutable_wrist_wrench());
  return frame;
}

void StampToWire(std::uint64_t frame_id, double sim_time_s, v1::FrameStamp* wire) {
  wire->set_frame_id(frame_id);
  wire->set_sim_time(sim_time_s);
}

void DescribeSpaces(const Model& model, v1::CreateSessionResponse* response) {
  const int dof = model.robot.dof();
  v1::ArraySpec* qpos = AddArraySpec(response, "agent/qpos", dof, "joint angles q1..q7 (rad)");
  for (const JointLimits& limits : model.robot.limits) {
    qpos->add_low(limits.lower_rad);
    qpos->add_high(limits.upper_rad);
  }
  AddArraySpec(response, "agent/qvel", dof, "joint velocities (rad/s)");
  AddArraySpec(response, "agent/qpos_target", dof, "joint targets of the PD controller (rad)");
  AddArraySpec(response, "extra/tcp_pose", 7, "knife TCP [x, y, z] (m) and [qw, qx, qy, qz], world frame");
  AddArraySpec(response, "extra/tcp_velocity", 6, "knife TCP [vx, vy, vz] (m/s), [wx, wy, wz] (rad/s), world");
  AddArraySpec(response, "extra/flange_pose", 7, "flange [x, y, z] (m) and [qw, qx, qy, qz], world frame");
  AddArraySpec(response, "extra/wrist_wrench", 6,
               "food on knife at the flange, flange frame: [fx, fy, fz] (N), [tx, ty, tz] (N m); zeros without food");

  DescribeCameraSpaces(model, response);

  for (ControlMode mode : AllControlModes()) {
    const ActionBounds bounds = ActionBoundsFor(model, mode);
    v1::ControlModeSpec* spec = response->add_control_modes();
    spec->set_name(ControlModeName(mode));
    v1::ArraySpec* action = spec->mutable_action();
    action->set_name("action");
    action->add_shape(static_cast<std::uint32_t>(bounds.low.size()));
    action->set_dtype("float64");
    action->mutable_low()->Assign(bounds.low.begin(), bounds.low.end());
    action->mutable_high()->Assign(bounds.high.begin(), bounds.high.end());
    action->set_description(bounds.description);
  }
  response->set_default_control_mode(ControlModeName(kDefaultControlMode));
  response->set_control_timestep(model.control_timestep_s);
}

}  // namespace culinarycut::server
