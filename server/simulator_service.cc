#include "server/simulator_service.h"

#include <chrono>

#include <spdlog/spdlog.h>

#include "server/access_control.h"
#include "server/status.h"
#include "server/version.h"
#include "server/wire/action.h"
#include "server/wire/observation.h"
#include "server/wire/safety.h"
#include "server/wire/scene.h"
#include "sim/mpm/kernel_instruction_set.h"
#include "sim/world/controller.h"
#include "sim/world/scene_budget.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"

namespace culinarycut::server {
SimulatorService::SimulatorService(RobotDescription robot, SessionManager* sessions, TelemetryPublisher* telemetry,
                                   SharedRenderer* renderer, CpuShare* cpu_share, SnapshotSeal seal,
                                   std::uint32_t max_handler_threads, SafetyModelSource safety_model,
                                   ConnectionLimits connections)
    : robot_(std::move(robot)),
      cpu_share_(cpu_share),
      sessions_(sessions),
      telemetry_(telemetry),
      renderer_(renderer),
      seal_(std::move(seal)),
      max_handler_threads_(max_handler_threads),
      connections_(connections),
      safety_model_(std::move(safety_model)) {}

double SimulatorService::ObserveToWire(Session& session, v1::FrameStamp* stamp, v1::Observation* wire,
                                       const safety::LimiterReport* step_report) {
  render::CameraRenderer* renderer = session.model->cameras.empty() ? nullptr : &renderer_->Get();
  const Observation observation = culinarycut::Observe(*session.model, session.state, renderer);
  StageTimes render_time;
  render_time[Stage::kRender] = observation.render_wall_time_ms;
  session.timers.Add(render_time);
  StampToWire(observation.frame_id, observation.sim_time_s, stamp);
  ObservationToWire(*session.model, observation, wire);
  if (telemetry_) telemetry_->Publish(session.telemetry_topic, TelemetryToWire(observation, step_report));
  return observation.render_wall_time_ms;
}

grpc::Status SimulatorService::GetServerInfo(grpc::ServerContext* context, const v1::GetServerInfoRequest*, v1::ServerInfo* info) {
  info->set_version(kServerVersion);
  info->set_build_id(kBuildId);
  info->set_simd(mpm::KernelInstructionSet());
  info->set_protocol("culinarycut.v1");
  for (const char* capability : {"robot", "snapshot", "health", "reflection", "tasks", "oracle", "mpm", "cameras"}) {
    info->add_capabilities(capability);
  }
  if (safety_model_.model) info->add_capabilities("safety_limiter");
  ForceModelToWire(safety_model_.path, safety_model_.model.get(), safety_model_.error, info->mutable_safety_model());
  if (telemetry_) {
    info->add_capabilities("telemetry");
    info->set_telemetry_endpoint(telemetry_->endpoint());
  }
  for (ControlMode mode : AllControlModes()) info->add_control_modes(ControlModeName(mode));
  info->mutable_limits()->set_max_sessions(sessions_->max_sessions());
  info->mutable_limits()->set_idle_timeout_s(sessions_->idle_timeout_s());
  v1::ServerLimits* limits = info->mutable_limits();
  limits->set_active_sessions(sessions_->size());
  limits->set_memory_budget_bytes(sessions_->memory_budget_bytes());
  limits->set_memory_reserved_bytes(sessions_->memory_reserved_bytes());
  limits->set_max_handler_threads(max_handler_threads_);
  limits->set_max_food_particles(kMaxFoodParticles);
  limits->set_max_mpm_substeps_per_step(kMaxMpmSubstepsPerControlStep);
  limits->set_max_camera_pixels(kMaxCameraPixelsPerSession);
  limits->set_step_cores(static_cast<std::uint32_t>(cpu_share_->cores()));
  limits->set_step_threads(cpu_share_->shared() ? "shared" : "model");
  limits->set_max_connections(connections_.max_connections);
  limits->set_max_connections_per_address(connections_.max_per_address);
  ResolutionCatalogueToWire(info);
  return grpc::Status::OK;
}

grpc::Status SimulatorService::CreateSession(grpc::ServerContext* context, const v1::CreateSessionRequest* request,
                                             v1::CreateSessionResponse* response) {
  return Guarded([&] {
    const SceneConfig config = SceneFromWire(request->scene());
    if (config.effects.safety_limiter && !safety_model_.model) {
      return MakeStatus(grpc::StatusCode::FAILED_PRECONDITION,
                        "scene.effects.safety_limiter needs the safety force model, which this server could not load: " +
                            safety_model_.error + " (start it with --safety-model PATH, or turn the limiter off)");
    }
    const std::shared_ptr<const Model> model = CompileModel(config, robot_, safety_model_.model);
    if (!model->cameras.empty()) {
      try {
        renderer_->Get();
      } catch (const render::RenderError& error) {
        return MakeStatus(grpc::StatusCode::FAILED_PRECONDITION,
                            std::string("scene.cameras need the headless renderer, which could not start on this "
                                        "server: ") + error.what() + " (or leave scene.cameras empty to run without images)");
      }
    }
    std::string refusal;
    const std::shared_ptr<Session> session = sessions_->Create(model, CallerPrincipal(*context), &refusal);
    if (!session) return MakeStatus(grpc::StatusCode::RESOURCE_EXHAUSTED, refusal);
    response->set_session_id(session->id);
    if (telemetry_) response->set_telemetry_topic(session->telemetry_topic);
    StampToWire(0, 0.0, response->mutable_stamp());
    DescribeSpaces(*model, response);
    *response->mutable_resolved_scene() = SceneToWire(model->config);
    if (model->food) ResolvedFoodToWire(*model->food, response->mutable_resolved_scene());
    spdlog::info("session {} created ({} sessions live)", session->id, sessions_->size());
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::Reset(grpc::ServerContext* context, const v1::ResetRequest* request, v1::ResetResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  return Guarded([&] {
    const std::uint64_t seed = request->has_seed() ? request->seed().value() : session->model->config.seed;
    ResetState(*session->model, &session->state, seed,
               std::vector<double>(request->initial_qpos().begin(), request->initial_qpos().end()));
    session->broken_reason.clear();
    session->oracle.reset();  // a new episode: the oracle's plan was for the old one
    response->set_seed(seed);
    ObserveToWire(*session, response->mutable_stamp(), response->mutable_observation());
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::Step(grpc::ServerContext* context, const v1::StepRequest* request, v1::StepResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  return Guarded([&] {
    const Action action = ActionFromWire(request->action());
    if (const auto error = ValidateAction(*session->model, action)) return InvalidArgument(*error);
    if (!session->state.has_been_reset()) return NotReset(*session);
    if (session->broken()) return Broken(*session);
    // A call whose client gave up (cancelled, deadline passed, server shutting down) is not worth
    // finishing: it is checked before the step and between its substeps, and a step it stops is
    // rolled back, so the client's view and the session's state never part.
    // The deadline is compared every time (cheap); gRPC's own cancellation flag costs about 20 us to
    // ask, so it is asked at most every 5 ms of wall time.
    auto next_check = std::chrono::steady_clock::now();
    const CancelCheck abandoned = [this, context, &next_check] {
      if (sessions_->stopping() || std::chrono::system_clock::now() > context->deadline()) return true;
      const auto now = std::chrono::steady_clock::now();
      if (now < next_check) return false;
      next_check = now + std::chrono::milliseconds(5);
      return CallAbandoned(*context);
    };
    if (abandoned()) return NotApplied(*context);
    StepResult result;
    const CpuShare::Seat seat(cpu_share_);
    try {
      result = culinarycut::Step(*session->model, &session->state, action, abandoned,
                                 [&seat] { return seat.Threads(); });
    } catch (const std::exception& error) {
      // The engine stopped half-way: the state is no longer one a simulation produced.
      session->broken_reason = std::string("Step failed at frame ") + std::to_string(session->state.frame_id) +
                               ": " + error.what();
      spdlog::error("session {}: {}", session->id, session->broken_reason);
      return MakeStatus(grpc::StatusCode::INTERNAL, session->broken_reason +
                                                          "; the session is now broken: call Reset or RestoreSnapshot");
    }
    if (result.cancelled && sessions_->stopping()) {
      return MakeStatus(grpc::StatusCode::UNAVAILABLE,
                        "the server is shutting down; the step was stopped and rolled back, nothing of it was applied");
    }
    if (result.cancelled) return NotApplied(*context);
    session->timers.Add(result.timings);
    const double render_ms = ObserveToWire(*session, response->mutable_stamp(), response->mutable_observation(),
                                           result.safety ? &*result.safety : nullptr);
    StepResultToWire(result, render_ms, response);
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::Observe(grpc::ServerContext* context, const v1::ObserveRequest* request, v1::ObserveResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  if (!session->state.has_been_reset()) return NotReset(*session);
  if (session->broken()) return Broken(*session);
  return Guarded([&] {
    ObserveToWire(*session, response->mutable_stamp(), response->mutable_observation());
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::CloseSession(grpc::ServerContext* context, const v1::CloseSessionRequest* request,
                                            v1::CloseSessionResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  {
    SessionLock lock(*session);  // let a call in flight finish first
    StampToWire(session->state.frame_id, session->state.sim_time_s, response->mutable_stamp());
  }
  sessions_->Close(session->id);
  spdlog::info("session {} closed ({} sessions live)", session->id, sessions_->size());
  session.reset();
  ReturnFreedMemory();
  return grpc::Status::OK;
}

grpc::Status SimulatorService::SaveSnapshot(grpc::ServerContext* context, const v1::SaveSnapshotRequest* request,
                                            v1::SaveSnapshotResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  if (!session->state.has_been_reset()) return NotReset(*session);
  if (session->broken()) return Broken(*session);
  return Guarded([&] {
    response->set_snapshot(seal_.Seal(culinarycut::SaveSnapshot(*session->model, session->state)));
    StampToWire(session->state.frame_id, session->state.sim_time_s, response->mutable_stamp());
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::RestoreSnapshot(grpc::ServerContext* context, const v1::RestoreSnapshotRequest* request,
                                               v1::RestoreSnapshotResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  return Guarded([&] {
    culinarycut::RestoreSnapshot(*session->model, seal_.Open(request->snapshot()), &session->state);
    session->broken_reason.clear();
    ObserveToWire(*session, response->mutable_stamp(), response->mutable_observation());
    return grpc::Status::OK;
  });
}

grpc::Status SimulatorService::GetSessionStats(grpc::ServerContext* context, const v1::GetSessionStatsRequest* request,
                                               v1::SessionStats* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) return status;
  SessionLock lock(*session);
  SessionStatsToWire(*session->model, session->state, session->timers, response);
  return grpc::Status::OK;
}

}  // namespace culinarycut::server
