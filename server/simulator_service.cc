#include "server/simulator_service.h"

#include <spdlog/spdlog.h>

#include "server/camera_wire_conversion.h"
#include "server/service_status.h"
#include "server/task_wire_conversion.h"
#include "server/version.h"
#include "server/wire_conversion.h"
#include "sim/world/camera_observation.h"
#include "sim/world/controller.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"

namespace culinarycut::server {

SimulatorService::SimulatorService(RobotDescription robot, SessionManager* sessions, TelemetryPublisher* telemetry,
                                   SharedRenderer* renderer)
    : robot_(std::move(robot)), sessions_(sessions), telemetry_(telemetry), renderer_(renderer) {}

grpc::Status SimulatorService::ObserveSession(Session& session, v1::FrameStamp* stamp, v1::Observation* observation,
                                              RobotObservation* robot_observation, double* render_ms) {
  *robot_observation = culinarycut::Observe(*session.model, session.state);
  StampToWire(robot_observation->frame_id, robot_observation->sim_time_s, stamp);
  ObservationToWire(*robot_observation, observation);
  FoodObservationToWire(session.state, observation);
  if (session.model->task) observation->set_instruction(session.model->task->instruction);
  if (session.model->cameras.empty()) return grpc::Status::OK;
  double elapsed_ms = 0.0;
  try {
    const render::RenderResult images = RenderCameras(renderer_->Get(), *session.model, &session.state, &elapsed_ms);
    CameraImagesToWire(*session.model, images, observation);
  } catch (const render::RenderError& error) {
    spdlog::error("session {}: rendering failed: {}", session.id, error.what());
    return grpc::Status(grpc::StatusCode::INTERNAL,
                        std::string("rendering the cameras failed: ") + error.what() +
                            "; the simulation state is intact (Observe retries the images)");
  }
  if (render_ms) *render_ms = elapsed_ms;
  return grpc::Status::OK;
}

void SimulatorService::PublishTelemetry(const Session& session, const RobotObservation& observation) {
  if (!telemetry_) return;
  telemetry_->Publish(TelemetryToWire(session.id, observation));
}

grpc::Status SimulatorService::GetServerInfo(grpc::ServerContext*, const v1::GetServerInfoRequest*, v1::ServerInfo* info) {
  info->set_version(kServerVersion);
  info->set_build_id(kBuildId);
  info->set_protocol("culinarycut.v1");
  for (const char* capability : {"robot", "snapshot", "health", "reflection", "tasks", "oracle", "mpm", "cameras"}) {
    info->add_capabilities(capability);
  }
  if (telemetry_) {
    info->add_capabilities("telemetry");
    info->set_telemetry_endpoint(telemetry_->endpoint());
  }
  for (ControlMode mode : AllControlModes()) info->add_control_modes(ControlModeName(mode));
  info->mutable_limits()->set_max_sessions(sessions_->max_sessions());
  info->mutable_limits()->set_idle_timeout_s(sessions_->idle_timeout_s());
  info->mutable_limits()->set_active_sessions(sessions_->size());
  return grpc::Status::OK;
}

grpc::Status SimulatorService::CreateSession(grpc::ServerContext*, const v1::CreateSessionRequest* request,
                                             v1::CreateSessionResponse* response) {
  SceneConfig config;
  if (grpc::Status status = SceneFromWire(request->scene(), &config); !status.ok()) return status;
  std::shared_ptr<const Model> model;
  try {
    model = CompileModel(config, robot_);
  } catch (const SceneError& error) {
    return InvalidArgument(error.what());
  }
  if (!model->cameras.empty()) {
    try {
      renderer_->Get();
    } catch (const render::RenderError& error) {
      return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                          std::string("scene.cameras need the headless renderer, which could not start on this server: ") +
                              error.what() + " (or leave scene.cameras empty to run without images)");
    }
  }
  const std::shared_ptr<Session> session = sessions_->Create(model);
  if (!session) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "the server already runs its maximum of " + std::to_string(sessions_->max_sessions()) +
                            " sessions; close one (CloseSession) or start the server with a larger --max-sessions");
  }
  response->set_session_id(session->id);
  StampToWire(0, 0.0, response->mutable_stamp());
  DescribeSpaces(*model, response);
  *response->mutable_resolved_scene() = SceneToWire(model->config);
  if (model->food) ResolvedFoodToWire(*model->food, response->mutable_resolved_scene());
  spdlog::info("session {} created ({} sessions live)", session->id, sessions_->size());
  return grpc::Status::OK;
}

grpc::Status SimulatorService::Reset(grpc::ServerContext*, const v1::ResetRequest* request, v1::ResetResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  std::lock_guard<std::mutex> lock(session->mutex);
  const std::uint64_t seed = request->has_seed() ? request->seed().value() : session->model->config.seed;
  try {
    ResetState(*session->model, &session->state, seed,
               std::vector<double>(request->initial_qpos().begin(), request->initial_qpos().end()));
    session->oracle.reset();  // a new episode: the oracle's plan was for the old one
  } catch (const SceneError& error) {
    return InvalidArgument(error.what());
  }
  RobotObservation observation;
  if (grpc::Status status = ObserveSession(*session, response->mutable_stamp(), response->mutable_observation(), &observation);
      !status.ok()) {
    return status;
  }
  response->set_seed(seed);
  PublishTelemetry(*session, observation);
  return grpc::Status::OK;
}

grpc::Status SimulatorService::Step(grpc::ServerContext*, const v1::StepRequest* request, v1::StepResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  const std::string& mode_name = request->action().control_mode();
  const std::optional<ControlMode> mode =
      mode_name.empty() ? std::optional<ControlMode>(kDefaultControlMode) : ParseControlMode(mode_name);
  if (!mode) {
    return InvalidArgument("action.control_mode '" + mode_name +
                           "' is unknown; use pd_joint_pos, pd_joint_delta_pos, pd_ee_pose or pd_ee_delta_pose");
  }
  const Action action{*mode, Eigen::Map<const Eigen::VectorXd>(request->action().values().data(),
                                                               request->action().values_size())};
  std::lock_guard<std::mutex> lock(session->mutex);
  if (const auto error = ValidateAction(*session->model, action)) return InvalidArgument(*error);
  if (!session->state.has_been_reset()) return NotReset(*session);

  const StepReport report = culinarycut::Step(*session->model, &session->state, action);
  RobotObservation observation;
  double render_ms = 0.0;
  if (grpc::Status status = ObserveSession(*session, response->mutable_stamp(), response->mutable_observation(),
                                           &observation, &render_ms);
      !status.ok()) {
    return status;
  }
  response->set_truncated(report.truncated);
  if (const std::optional<TaskModel>& task = session->model->task) {
    // ManiSkill's sparse reward: 1 while the task is done; the episode terminates once it is.
    const task::TaskScore score = EvaluateTask(*task, *session->model->food, *session->state.food);
    TaskScoreToWire(score, response->mutable_task_score());
    response->set_reward(score.success ? 1.0 : 0.0);
    response->set_terminated(score.success);
  }
  v1::StepInfo* info = response->mutable_info();
  info->set_substeps(report.substeps);
  info->set_action_clipped(report.action_clipped);
  if (report.ik) {
    info->set_ik_converged(report.ik->converged);
    info->set_ik_position_error(report.ik->position_error_m);
    info->set_ik_orientation_error(report.ik->orientation_error_rad);
  }
  info->set_step_wall_time_ms(report.wall_time_ms);
  info->set_control_wall_time_ms(report.control_wall_time_ms);
  info->set_physics_wall_time_ms(report.physics_wall_time_ms);
  info->set_mpm_substeps(static_cast<std::uint32_t>(report.mpm_substeps));
  info->set_mpm_wall_time_ms(report.mpm_wall_time_ms);
  info->set_topology_wall_time_ms(report.topology_wall_time_ms);
  info->set_first_contact(report.first_contact);
  info->set_render_wall_time_ms(render_ms);
  PublishTelemetry(*session, observation);
  return grpc::Status::OK;
}

grpc::Status SimulatorService::Observe(grpc::ServerContext*, const v1::ObserveRequest* request, v1::ObserveResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  std::lock_guard<std::mutex> lock(session->mutex);
  if (!session->state.has_been_reset()) return NotReset(*session);
  RobotObservation observation;
  return ObserveSession(*session, response->mutable_stamp(), response->mutable_observation(), &observation);
}

grpc::Status SimulatorService::CloseSession(grpc::ServerContext*, const v1::CloseSessionRequest* request,
                                            v1::CloseSessionResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  {
    std::lock_guard<std::mutex> lock(session->mutex);  // let a call in flight finish first
    StampToWire(session->state.frame_id, session->state.sim_time_s, response->mutable_stamp());
  }
  sessions_->Close(session->id);
  spdlog::info("session {} closed ({} sessions live)", session->id, sessions_->size());
  return grpc::Status::OK;
}

grpc::Status SimulatorService::SaveSnapshot(grpc::ServerContext*, const v1::SaveSnapshotRequest* request,
                                            v1::SaveSnapshotResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  std::lock_guard<std::mutex> lock(session->mutex);
  if (!session->state.has_been_reset()) return NotReset(*session);
  response->set_snapshot(culinarycut::SaveSnapshot(*session->model, session->state));
  StampToWire(session->state.frame_id, session->state.sim_time_s, response->mutable_stamp());
  return grpc::Status::OK;
}

grpc::Status SimulatorService::RestoreSnapshot(grpc::ServerContext*, const v1::RestoreSnapshotRequest* request,
                                               v1::RestoreSnapshotResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  std::lock_guard<std::mutex> lock(session->mutex);
  try {
    culinarycut::RestoreSnapshot(*session->model, request->snapshot(), &session->state);
  } catch (const SnapshotError& error) {
    return InvalidArgument(std::string("snapshot: ") + error.what());
  }
  RobotObservation observation;
  if (grpc::Status status = ObserveSession(*session, response->mutable_stamp(), response->mutable_observation(), &observation);
      !status.ok()) {
    return status;
  }
  PublishTelemetry(*session, observation);
  return grpc::Status::OK;
}

}  // namespace culinarycut::server

namespace culinarycut::server {

grpc::Status SimulatorService::GetSessionStats(grpc::ServerContext*, const v1::GetSessionStatsRequest* request,
                                               v1::SessionStats* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, request->session_id(), &session); !status.ok()) return status;
  std::lock_guard<std::mutex> lock(session->mutex);
  SessionStatsToWire(*session->model, session->state, response);
  return grpc::Status::OK;
}

}  // namespace culinarycut::server
