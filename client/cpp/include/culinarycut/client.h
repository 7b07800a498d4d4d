// C++ client for the CulinaryCut server (culinarycut.v1 over gRPC).
//
//   culinarycut::Client client("127.0.0.1:50051");
//   auto session = client.CreateSession();          // closed when it goes out of scope
//   culinarycut::Observation obs = session->Reset(/*seed=*/0);
//   auto result = session->Step("pd_ee_delta_pose", {0, 0, -0.01, 0, 0, 0});
//
// Every failed call throws culinarycut::RpcError, which carries the gRPC status code and the
// server's message.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "culinarycut/v1/simulator.grpc.pb.h"
#include "culinarycut/v1/task.grpc.pb.h"

namespace culinarycut {

class RpcError : public std::runtime_error {
 public:
  RpcError(const std::string& method, const grpc::Status& status);
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

// One observation, in SI units; poses are [x, y, z, qw, qx, qy, qz] in the world frame.
struct Observation {
  std::uint64_t frame_id = 0;
  double sim_time = 0.0;
  std::vector<double> qpos, qvel, qpos_target;
  std::vector<double> tcp_pose, tcp_velocity, flange_pose;
};

struct StepResult {
  Observation observation;
  double reward = 0.0;
  bool terminated = false;
  bool truncated = false;
  v1::StepInfo info;
};

class Session;

class Client {
 public:
  explicit Client(const std::string& address, std::chrono::milliseconds call_timeout = std::chrono::seconds(30));

  // True once the server answers; false after `timeout`.
  bool WaitForServer(std::chrono::milliseconds timeout);
  v1::ServerInfo GetServerInfo();
  std::unique_ptr<Session> CreateSession(const v1::SceneSpec& scene = {});

  // The raw stubs, for calls this wrapper does not cover.
  v1::Simulator::Stub& stub() { return *stub_; }
  v1::Tasks::Stub& tasks_stub() { return *tasks_stub_; }

  // Stateless task calls (the Tasks service): instruction -> spec, planning, scoring.
  v1::ParseInstructionResponse ParseInstruction(const std::string& instruction);
  std::vector<std::string> GenerateInstructions(const v1::GenerateInstructionsRequest& request);
  v1::CutPlan PlanCut(const v1::PlanCutRequest& request);
  v1::TaskScore ScoreCuts(const v1::ScoreCutsRequest& request);
  // A context with this client's deadline.
  std::unique_ptr<grpc::ClientContext> MakeContext() const;

 private:
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Simulator::Stub> stub_;
  std::unique_ptr<v1::Tasks::Stub> tasks_stub_;
  std::chrono::milliseconds call_timeout_;
};

class Session {
 public:
  Session(Client* client, v1::CreateSessionResponse handshake);
  ~Session();  // closes the session on the server; errors are ignored here
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
  void Close();

  // The server-side scripted oracle: plan once per episode (session_id is filled in), then one
  // action per step:  while (!(a = OracleAction()).finished()) Step(a.action().control_mode(), ...).
  v1::CutPlan StartOracle(v1::StartOracleRequest request);
  v1::OracleActionResponse OracleAction();

 private:
  Client* client_;
  v1::CreateSessionResponse handshake_;
  bool closed_ = false;
};

// Converts a wire observation (and its stamp) into the plain struct.
Observation FromWire(const v1::FrameStamp& stamp, const v1::Observation& wire);

}  // namespace culinarycut
