#include "server/simulation_server.h"

#include <arpa/inet.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/resource_quota.h>
#include <spdlog/spdlog.h>

#include "server/field_detail.h"
#include "sim/world/model.h"

namespace culinarycut::server {

namespace {

// gRPC quietly wraps ports above 65535; refuse them instead.
void CheckListenAddress(const std::string& address) {
  if (address.rfind("unix:", 0) == 0) return;
  const size_t colon = address.rfind(':');
  const std::string port = colon == std::string::npos ? "" : address.substr(colon + 1);
  const bool digits = !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoi(port) > 65535) {
    throw std::runtime_error("--listen " + address + ": expected host:port with a port in 0..65535 (0 picks a free "
                             "port), or unix:///path/to.sock");
  }
}

// Loopback hosts (127.0.0.0/8, localhost, [::1]) and unix sockets: reachable only from this machine.
bool IsLoopbackOrUnix(const std::string& address) {
  if (address.rfind("unix:", 0) == 0) return true;
  std::string host = address.substr(0, address.rfind(':'));
  if (host.rfind("ipv4:", 0) == 0) host = host.substr(5);
  if (host == "localhost" || host == "[::1]") return true;
  // 127.0.0.0/8 as a dotted quad only: a host name such as 127.example.com is not loopback.
  in_addr parsed{};
  return inet_pton(AF_INET, host.c_str(), &parsed) == 1 && (ntohl(parsed.s_addr) >> 24) == 127;
}

// The sessions' memory budget: the flag, or three quarters of the machine's memory.
std::uint64_t MemoryBudgetBytes(std::uint64_t budget_mb) {
  if (budget_mb > 0) return budget_mb << 20;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? static_cast<std::uint64_t>(pages) * page_size / 4 * 3 : 0;
}

}  // namespace

SimulationServer::SimulationServer(const ServerOptions& options) {
  if (options.max_sessions == 0) throw std::runtime_error("--max-sessions must be at least 1");
  if (!(options.idle_timeout_s > 0)) throw std::runtime_error("--idle-timeout must be a positive number of seconds");
  CheckListenAddress(options.listen_address);
  const std::shared_ptr<grpc::ServerCredentials> credentials = MakeServerCredentials(options.access);
  const bool protected_port = !options.access.tls_cert_file.empty() && Authenticates(options.access);
  if (!options.insecure && !protected_port && !IsLoopbackOrUnix(options.listen_address)) {
    throw std::runtime_error("--listen " + options.listen_address +
                             " is not a loopback address: off loopback the server needs TLS (--tls-cert, --tls-key) "
                             "and authentication (--token-file or --tls-client-ca), else anyone who reaches it could "
                             "drive or close every session. Listen on 127.0.0.1 (and tunnel, e.g. ssh -L), add them, "
                             "or pass --insecure to accept the risk");
  }
  // Telemetry goes over tcp:// (loopback unless --insecure) or ipc:// (a local socket file); ZeroMQ's other
  // transports (pgm, epgm, udp, ws, tipc, vmci, ...) reach beyond this machine and are refused by name.
  const std::string& telemetry = options.telemetry_endpoint;
  const std::string transport = telemetry.substr(0, telemetry.find("://"));
  if (!telemetry.empty() && transport != "tcp" && transport != "ipc") {
    throw std::runtime_error("--telemetry " + telemetry + ": transport '" + transport +
                             "' is not allowed; use tcp://127.0.0.1:PORT or ipc:///path");
  }
  const std::string telemetry_host = transport == "tcp" ? telemetry.substr(6) : std::string("127.0.0.1:0");
  if (!options.insecure && !options.telemetry_endpoint.empty() && !IsLoopbackOrUnix(telemetry_host)) {
    throw std::runtime_error("--telemetry " + options.telemetry_endpoint +
                             " is not on loopback: telemetry shows every session's robot state and is not "
                             "encrypted. Bind it to tcp://127.0.0.1:PORT, or pass --insecure to accept the risk");
  }
  if (options.insecure && !protected_port && !IsLoopbackOrUnix(options.listen_address)) {
    spdlog::warn("--insecure: listening on {} without TLS and authentication; anyone who reaches it controls every "
                 "session", options.listen_address);
  }
  if (options.insecure && !options.telemetry_endpoint.empty() && !IsLoopbackOrUnix(telemetry_host)) {
    spdlog::warn("--insecure: telemetry on {} off loopback, unencrypted; anyone who reaches it sees every session",
                 options.telemetry_endpoint);
  }
  const std::string urdf = options.robot_urdf_path.empty() ? DefaultRobotUrdfPath() : options.robot_urdf_path;
  RobotDescription robot = LoadRobotDescription(urdf, kTcpFrame);
  // Fail at start, not on the first CreateSession, if the robot cannot make a default scene.
  try {
    CompileModel(SceneConfig{}, robot);
  } catch (const SceneError& error) {
    throw std::runtime_error(urdf + ": " + error.what());
  }
  if (!options.telemetry_endpoint.empty()) {
    try {
      telemetry_ = std::make_unique<TelemetryPublisher>(options.telemetry_endpoint);
    } catch (const std::exception& error) {
      throw std::runtime_error("cannot bind telemetry endpoint " + options.telemetry_endpoint + ": " + error.what() +
                               " (pick another with --telemetry, or --telemetry '' to turn it off)");
    }
  }
  if (options.max_handler_threads < 4) throw std::runtime_error("--max-handler-threads must be at least 4");
  sessions_ = std::make_unique<SessionManager>(options.max_sessions, std::chrono::duration<double>(options.idle_timeout_s),
                                               MemoryBudgetBytes(options.memory_budget_mb),
                                               options.max_sessions_per_owner);
  render::RendererOptions render_options;
  render_options.robot = robot.visuals;  // the URDF parsed once, by the robot description
  renderer_ = std::make_unique<SharedRenderer>(render_options);
  SafetyModelSource safety_model = LoadSafetyModel(
      options.safety_model_path.empty() ? safety::DefaultForceModelPath() : options.safety_model_path);
  if (options.step_threads != "shared" && options.step_threads != "model") {
    throw std::runtime_error("--step-threads must be shared or model, not '" + options.step_threads + "'");
  }
  cpu_share_ = std::make_unique<CpuShare>(static_cast<int>(options.step_cores), options.step_threads == "shared");
  // A TCP port is the gate's: it caps connections and relays them to gRPC on a private unix socket.
  const bool unix_socket = options.listen_address.rfind("unix:", 0) == 0;
  if (!unix_socket) gate_ = std::make_unique<ConnectionGate>(options.listen_address, options.connections);
  service_ = std::make_unique<SimulatorService>(std::move(robot), sessions_.get(), telemetry_.get(), renderer_.get(),
                                                cpu_share_.get(), SnapshotSeal(options.snapshot_key_file),
                                                options.max_handler_threads, std::move(safety_model),
                                                gate_ ? gate_->limits() : ConnectionLimits{0, 0});
  task_service_ = std::make_unique<TaskService>(sessions_.get());

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  // One server per port: with port reuse on, a second server on a taken port would share its
  // incoming connections and clients would lose their sessions at random.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  // A connection that has not finished its TLS/HTTP2 handshake in 10 s, or has carried no call for 10
  // minutes, is closed: idle sockets from a flood give their descriptors back.
  builder.AddChannelArgument(GRPC_ARG_SERVER_HANDSHAKE_TIMEOUT_MS, 10'000);
  builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_IDLE_MS, 600'000);
  // A bounded thread pool: 1,000 concurrent calls must not become 1,000 threads.
  grpc::ResourceQuota quota("culinarycut-server");
  quota.SetMaxThreads(static_cast<int>(options.max_handler_threads));
  builder.SetResourceQuota(quota);
  int bound_port = 0;
  builder.AddListeningPort(unix_socket ? options.listen_address : gate_->backend_address(), credentials, &bound_port);
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(std::make_unique<FieldDetailInterceptorFactory>());
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  builder.RegisterService(service_.get());
  builder.RegisterService(task_service_.get());
  server_ = builder.BuildAndStart();
  if (!server_ || bound_port == 0) {
    throw std::runtime_error("cannot listen on " + options.listen_address +
                             " (port in use or address invalid); pick another with --listen, e.g. 127.0.0.1:0");
  }
  if (gate_) {
    gate_->Start();
    spdlog::info("connections: at most {}, {} per client address", gate_->limits().max_connections,
                 gate_->limits().max_per_address);
  }
  // unix:PATH sockets have no port; tcp addresses report the one actually bound (port 0 picks one).
  server_->GetHealthCheckService()->SetServingStatus(v1::Simulator::service_full_name(), true);
  server_->GetHealthCheckService()->SetServingStatus(v1::Tasks::service_full_name(), true);
  address_ = unix_socket ? options.listen_address
                         : options.listen_address.substr(0, options.listen_address.rfind(':')) + ":" +
                               std::to_string(gate_->port());
}

SimulationServer::~SimulationServer() { Shutdown(); }

std::string SimulationServer::telemetry_endpoint() const { return telemetry_ ? telemetry_->endpoint() : ""; }

void SimulationServer::Shutdown() {
  if (server_) {
    // A Step in flight stops at its next check and rolls back now; other calls get 1 s to finish, then
    // they are cancelled.
    if (gate_) gate_->StopAccepting();
    sessions_->BeginStopping();
    server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
    server_->Wait();
    server_.reset();
  }
  // After gRPC: its goodbyes (GOAWAY) to the clients go through the gate.
  if (gate_) gate_->Stop();
}

}  // namespace culinarycut::server
