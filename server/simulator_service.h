// The culinarycut.v1.Simulator gRPC service: validates every request, then runs it on its session.
// A bad request gets a status code and a message naming the field; it never takes the server down.
#pragma once

#include <memory>
#include <string>

#include "culinarycut/v1/simulator.grpc.pb.h"
#include "server/connection_gate.h"
#include "server/safety_model.h"
#include "server/session_manager.h"
#include "server/shared_renderer.h"
#include "server/snapshot_seal.h"
#include "server/telemetry_publisher.h"
#include "sim/safety/limiter.h"
#include "server/cpu_share.h"
#include "sim/robot/robot_description.h"

namespace culinarycut::server {

class SimulatorService final : public v1::Simulator::Service {
 public:
  // `telemetry` may be null (telemetry off); `renderer` starts only when a scene declares cameras;
  // `safety_model` without a model refuses scenes with the safety limiter (FAILED_PRECONDITION).
  // `cpu_share` divides the cores among the Steps running at once.
  SimulatorService(RobotDescription robot, SessionManager* sessions, TelemetryPublisher* telemetry,
                   SharedRenderer* renderer, CpuShare* cpu_share, SnapshotSeal seal,
                   std::uint32_t max_handler_threads, SafetyModelSource safety_model,
                   ConnectionLimits connections = {0, 0});

  grpc::Status GetServerInfo(grpc::ServerContext*, const v1::GetServerInfoRequest*, v1::ServerInfo*) override;
  grpc::Status CreateSession(grpc::ServerContext*, const v1::CreateSessionRequest*, v1::CreateSessionResponse*) override;
  grpc::Status Reset(grpc::ServerContext*, const v1::ResetRequest*, v1::ResetResponse*) override;
  grpc::Status Step(grpc::ServerContext*, const v1::StepRequest*, v1::StepResponse*) override;
  grpc::Status Observe(grpc::ServerContext*, const v1::ObserveRequest*, v1::ObserveResponse*) override;
  grpc::Status CloseSession(grpc::ServerContext*, const v1::CloseSessionRequest*, v1::CloseSessionResponse*) override;
  grpc::Status SaveSnapshot(grpc::ServerContext*, const v1::SaveSnapshotRequest*, v1::SaveSnapshotResponse*) override;
  grpc::Status RestoreSnapshot(grpc::ServerContext*, const v1::RestoreSnapshotRequest*, v1::RestoreSnapshotResponse*) override;
  grpc::Status GetSessionStats(grpc::ServerContext*, const v1::GetSessionStatsRequest*, v1::SessionStats*) override;

 private:
  // Observes the session's current state (engine Observe, cameras rendered), writes the stamp and
  // the observation, publishes telemetry and adds the render time to the session's timers.
  // Throws render::RenderError when the renderer fails mid-episode; returns the render time (ms).
  // Observes the session into `observation` and publishes its telemetry frame (with the Step's limiter report).
  double ObserveToWire(Session& session, v1::FrameStamp* stamp, v1::Observation* observation,
                       const safety::LimiterReport* step_report = nullptr);

  const RobotDescription robot_;
  CpuShare* cpu_share_;
  SessionManager* sessions_;
  TelemetryPublisher* telemetry_;
  SharedRenderer* renderer_;
  const SnapshotSeal seal_;
  const std::uint32_t max_handler_threads_;  // published in GetServerInfo
  const ConnectionLimits connections_;       // the connection gate's caps, published; zero: a unix socket
  const SafetyModelSource safety_model_;
};

}  // namespace culinarycut::server
