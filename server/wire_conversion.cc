#include "server/wire_conversion.h"

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

}  // namespace

grpc::Status SceneFromWire(const v1::SceneSpec& wire, SceneConfig* config) {
  if (wire.objects_size() > 0) return Unimplemented("scene.objects", "MPM food simulation");
  if (wire.cameras_size() > 0) return Unimplemented("scene.cameras", "camera rendering");
  if (wire.has_task()) return Unimplemented("scene.task", "cutting tasks");
  if (wire.scene() == "kitchen") return Unimplemented("scene.scene=\"kitchen\"", "the kitchen scene");
  const v1::Effects& effects = wire.effects();
  if (effects.mpm() || effects.plasticity() || effects.damage() || effects.friction() || effects.topology() ||
      effects.force_sensing() || effects.safety_limiter()) {
    return Unimplemented("scene.effects", "MPM cutting effects and the safety limiter");
  }

  SceneConfig parsed;
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
}

v1::TelemetryFrame TelemetryToWire(const std::string& session_id, const RobotObservation& observation) {
  v1::TelemetryFrame frame;
  frame.set_session_id(session_id);
  StampToWire(observation.frame_id, observation.sim_time_s, frame.mutable_stamp());
  AssignVector(observation.qpos_rad, frame.mutable_qpos());
  AssignVector(observation.qvel_rad_s, frame.mutable_qvel());
  AssignVector(observation.tcp_pose, frame.mutable_tcp_pose());
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
