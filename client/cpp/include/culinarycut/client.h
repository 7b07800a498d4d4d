// C++ client for the CulinaryCut server (culinarycut.v1 over gRPC).
//
//   culinarycut::client::Client client("127.0.0.1:50051");
//   auto session = client.CreateSession();          // closed when it goes out of scope
//   culinarycut::client::Observation obs = session->Reset(/*seed=*/0);
//   auto result = session->Step("pd_ee_delta_pose", {0, 0, -0.1, 0, 0, 0});   // normalised: 1 cm down
//
// Every failed call throws culinarycut::client::RpcError, which carries the gRPC status code and
// the server's message (it names the field at fault for bad input). A Session keeps the
// connection alive on its own, so it may outlive the Client that created it. Use from another
// CMake project: find_package(culinarycut CONFIG REQUIRED) and link culinarycut::client.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "culinarycut/observation.h"
#include "culinarycut/v1/simulator.grpc.pb.h"
#include "culinarycut/v1/task.grpc.pb.h"

namespace culinarycut::client {

class RpcError : public std::runtime_error {
 public:
  RpcError(const std::string& method, const grpc::Status& status, std::string field = "");
  grpc::StatusCode code() const { return code_; }
  const std::string& details() const { return details_; }  // the server's message alone
  // For INVALID_ARGUMENT: the path of the field at fault (e.g. "scene.objects[0].scale"), or "".
  const std::string& field() const { return field_; }

 private:
  grpc::StatusCode code_;
  std::string details_;
  std::string field_;
};

// How to reach a server started with --tls-cert (and --token-file or --tls-client-ca). Empty: plaintext.
struct ConnectionOptions {
  std::chrono::milliseconds call_timeout = std::chrono::seconds(30);
  bool tls = false;                 // set by any of the PEM fields; set alone: TLS with the system's roots
  std::string tls_root_certs_pem;   // the CA that signed the server's certificate
  std::string tls_client_cert_pem;  // for servers that ask for client certificates
  std::string tls_client_key_pem;
  std::string token;                // bearer token (sent only over TLS)
};

// The channel, the stubs and the per-call deadline, shared by a Client and its Sessions.
class Connection {
 public:
  Connection(const std::string& address, const ConnectionOptions& options);
  v1::Simulator::Stub& simulator() { return *simulator_; }
  v1::Tasks::Stub& tasks() { return *tasks_; }
  grpc::Channel& channel() { return *channel_; }
  // A context with this connection's deadline.
  std::unique_ptr<grpc::ClientContext> MakeContext() const;

 private:
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Simulator::Stub> simulator_;
  std::unique_ptr<v1::Tasks::Stub> tasks_;
  std::chrono::milliseconds call_timeout_;
};

class Session;

class Client {
 public:
  explicit Client(const std::string& address, std::chrono::milliseconds call_timeout = std::chrono::seconds(30));
  Client(const std::string& address, const ConnectionOptions& options);

  // True once the server answers; false after `timeout`.
  bool WaitForServer(std::chrono::milliseconds timeout);
  v1::ServerInfo GetServerInfo();
  std::unique_ptr<Session> CreateSession(const v1::SceneSpec& scene = {});
  // A session created by someone else (a policy server is lent the runner's): its calls work as on
  // your own, but it stays open when the object goes away, and handshake() holds only its id.
  std::unique_ptr<Session> AttachSession(const std::string& session_id);

  // Stateless task calls (the Tasks service): instruction -> spec, planning, scoring.
  v1::ParseInstructionResponse ParseInstruction(const std::string& instruction);
  std::vector<std::string> GenerateInstructions(const v1::GenerateInstructionsRequest& request);
  v1::CutPlan PlanCut(const v1::PlanCutRequest& request);
  v1::TaskScore ScoreCuts(const v1::ScoreCutsRequest& request);

  // The raw stubs and contexts, for calls this wrapper does not cover.
  v1::Simulator::Stub& stub() { return connection_->simulator(); }
  v1::Tasks::Stub& tasks_stub() { return connection_->tasks(); }
  std::unique_ptr<grpc::ClientContext> MakeContext() const { return connection_->MakeContext(); }

 private:
  std::shared_ptr<Connection> connection_;
};

class Session {
 public:
  // `owned`: the session is closed on the server when this object goes away.
  Session(std::shared_ptr<Connection> connection, v1::CreateSessionResponse handshake, bool owned = true);
  ~Session();  // closes an owned session on the server; never throws
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const std::string& id() const { return handshake_.session_id(); }
  // Observation and action specs, control modes, control timestep, resolved scene.
  const v1::CreateSessionResponse& handshake() const { return handshake_; }

  Observation Reset(std::optional<std::uint64_t> seed = std::nullopt, const std::vector<double>& initial_qpos = {});
  StepResult Step(const std::string& control_mode, const std::vector<double>& values);
  Observation Observe();
  std::string SaveSnapshot();
  Observation RestoreSnapshot(const std::string& snapshot);
  // What the session has built and run: MPM allocation, particles, substeps, stage wall times.
  v1::SessionStats GetSessionStats();
  void Close();

  // The server-side scripted oracle: plan once per episode (session_id is filled in), then one
  // action per step:  while (!(a = OracleAction()).finished()) Step(a.action().control_mode(), ...).
  v1::CutPlan StartOracle(v1::StartOracleRequest request);
  v1::OracleActionResponse OracleAction();

 private:
  std::shared_ptr<Connection> connection_;
  v1::CreateSessionResponse handshake_;
  bool owned_ = true;
  bool closed_ = false;
};

}  // namespace culinarycut::client
