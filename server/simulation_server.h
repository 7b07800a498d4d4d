// The whole server as an object: gRPC service, health and reflection, sessions, telemetry.
// main() and the end-to-end tests both run it this way.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "server/connection_gate.h"
#include "server/server_options.h"
#include "server/cpu_share.h"
#include "server/session_manager.h"
#include "server/shared_renderer.h"
#include "server/simulator_service.h"
#include "server/task_service.h"
#include "server/telemetry_publisher.h"

namespace culinarycut::server {

class SimulationServer {
 public:
  // Loads the robot, binds the sockets and starts serving. Throws std::runtime_error with a
  // message a person can act on (port in use, bad URDF, bad telemetry endpoint).
  explicit SimulationServer(const ServerOptions& options);
  ~SimulationServer();

  // "host:port" with the port actually bound.
  const std::string& address() const { return address_; }
  // The telemetry endpoint actually bound; empty when telemetry is off.
  std::string telemetry_endpoint() const;
  SessionManager& sessions() { return *sessions_; }

  // Stops accepting calls, lets calls in flight finish (up to 1 s), then returns.
  void Shutdown();

 private:
  std::unique_ptr<ConnectionGate> gate_;  // declared before server_, so destroyed after gRPC has stopped
  std::unique_ptr<TelemetryPublisher> telemetry_;
  std::unique_ptr<SharedRenderer> renderer_;
  std::unique_ptr<SessionManager> sessions_;
  std::unique_ptr<CpuShare> cpu_share_;
  std::unique_ptr<SimulatorService> service_;
  std::unique_ptr<TaskService> task_service_;
  std::unique_ptr<grpc::Server> server_;
  std::string address_;
};

}  // namespace culinarycut::server
