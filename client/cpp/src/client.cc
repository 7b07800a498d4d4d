#include "culinarycut/client.h"

namespace culinarycut::client {
namespace {

void Check(const char* method, const grpc::Status& status) {
  if (!status.ok()) throw RpcError(method, status);
}

}  // namespace

RpcError::RpcError(const std::string& method, const grpc::Status& status)
    : std::runtime_error(method + " failed (gRPC code " + std::to_string(status.error_code()) + "): " +
                         status.error_message()),
      code_(status.error_code()),
      details_(status.error_message()) {}

namespace {

// Replies with camera images exceed gRPC's default 4 MB (three 640x480 RGB-D-segmentation views are 10 MB).
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& address) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(512 * 1024 * 1024);
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments);
}

}  // namespace

Connection::Connection(const std::string& address, std::chrono::milliseconds call_timeout)
    : channel_(MakeChannel(address)),
      simulator_(v1::Simulator::NewStub(channel_)),
      tasks_(v1::Tasks::NewStub(channel_)),
      call_timeout_(call_timeout) {}

std::unique_ptr<grpc::ClientContext> Connection::MakeContext() const {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() + call_timeout_);
  return context;
}

Client::Client(const std::string& address, std::chrono::milliseconds call_timeout)
    : connection_(std::make_shared<Connection>(address, call_timeout)) {}

bool Client::WaitForServer(std::chrono::milliseconds timeout) {
  return connection_->channel().WaitForConnected(std::chrono::system_clock::now() + timeout);
}

v1::ServerInfo Client::GetServerInfo() {
  v1::ServerInfo info;
  Check("GetServerInfo", stub().GetServerInfo(MakeContext().get(), v1::GetServerInfoRequest(), &info));
  return info;
}

std::unique_ptr<Session> Client::CreateSession(const v1::SceneSpec& scene) {
  v1::CreateSessionRequest request;
  *request.mutable_scene() = scene;
  v1::CreateSessionResponse response;
  Check("CreateSession", stub().CreateSession(MakeContext().get(), request, &response));
  return std::make_unique<Session>(connection_, std::move(response));
}

v1::ParseInstructionResponse Client::ParseInstruction(const std::string& instruction) {
  v1::ParseInstructionRequest request;
  request.set_instruction(instruction);
  v1::ParseInstructionResponse response;
  Check("ParseInstruction", tasks_stub().ParseInstruction(MakeContext().get(), request, &response));
  return response;
}

std::vector<std::string> Client::GenerateInstructions(const v1::GenerateInstructionsRequest& request) {
  v1::GenerateInstructionsResponse response;
  Check("GenerateInstructions", tasks_stub().GenerateInstructions(MakeContext().get(), request, &response));
  return {response.instructions().begin(), response.instructions().end()};
}

v1::CutPlan Client::PlanCut(const v1::PlanCutRequest& request) {
  v1::PlanCutResponse response;
  Check("PlanCut", tasks_stub().PlanCut(MakeContext().get(), request, &response));
  return response.plan();
}

v1::TaskScore Client::ScoreCuts(const v1::ScoreCutsRequest& request) {
  v1::ScoreCutsResponse response;
  Check("ScoreCuts", tasks_stub().ScoreCuts(MakeContext().get(), request, &response));
  return response.score();
}

Session::Session(std::shared_ptr<Connection> connection, v1::CreateSessionResponse handshake)
    : connection_(std::move(connection)), handshake_(std::move(handshake)) {}

Session::~Session() {
  try {
    Close();
  } catch (...) {
    // The server may already have reclaimed or lost the session; nothing to undo.
  }
}

Observation Session::Reset(std::optional<std::uint64_t> seed, const std::vector<double>& initial_qpos) {
  v1::ResetRequest request;
  request.set_session_id(id());
  if (seed) request.mutable_seed()->set_value(*seed);
  request.mutable_initial_qpos()->Assign(initial_qpos.begin(), initial_qpos.end());
  v1::ResetResponse response;
  Check("Reset", connection_->simulator().Reset(connection_->MakeContext().get(), request, &response));
  return FromWire(response.stamp(), response.observation());
}

StepResult Session::Step(const std::string& control_mode, const std::vector<double>& values) {
  v1::StepRequest request;
  request.set_session_id(id());
  request.mutable_action()->set_control_mode(control_mode);
  request.mutable_action()->mutable_values()->Assign(values.begin(), values.end());
  v1::StepResponse response;
  Check("Step", connection_->simulator().Step(connection_->MakeContext().get(), request, &response));
  StepResult result;
  result.observation = FromWire(response.stamp(), response.observation());
  result.reward = response.reward();
  if (response.has_task_score()) {
    result.task_score = response.task_score();
    result.success = response.task_score().success();
  }
  result.terminated = response.terminated();
  result.truncated = response.truncated();
  result.info = response.info();
  return result;
}

Observation Session::Observe() {
  v1::ObserveRequest request;
  request.set_session_id(id());
  v1::ObserveResponse response;
  Check("Observe", connection_->simulator().Observe(connection_->MakeContext().get(), request, &response));
  return FromWire(response.stamp(), response.observation());
}

std::string Session::SaveSnapshot() {
  v1::SaveSnapshotRequest request;
  request.set_session_id(id());
  v1::SaveSnapshotResponse response;
  Check("SaveSnapshot", connection_->simulator().SaveSnapshot(connection_->MakeContext().get(), request, &response));
  return response.snapshot();
}

Observation Session::RestoreSnapshot(const std::string& snapshot) {
  v1::RestoreSnapshotRequest request;
  request.set_session_id(id());
  request.set_snapshot(snapshot);
  v1::RestoreSnapshotResponse response;
  Check("RestoreSnapshot", connection_->simulator().RestoreSnapshot(connection_->MakeContext().get(), request, &response));
  return FromWire(response.stamp(), response.observation());
}

v1::SessionStats Session::GetSessionStats() {
  v1::GetSessionStatsRequest request;
  request.set_session_id(id());
  v1::SessionStats response;
  Check("GetSessionStats", connection_->simulator().GetSessionStats(connection_->MakeContext().get(), request, &response));
  return response;
}

void Session::Close() {
  if (closed_) return;
  closed_ = true;
  v1::CloseSessionRequest request;
  request.set_session_id(id());
  v1::CloseSessionResponse response;
  Check("CloseSession", connection_->simulator().CloseSession(connection_->MakeContext().get(), request, &response));
}

v1::CutPlan Session::StartOracle(v1::StartOracleRequest request) {
  request.set_session_id(id());
  v1::StartOracleResponse response;
  Check("StartOracle", connection_->tasks().StartOracle(connection_->MakeContext().get(), request, &response));
  return response.plan();
}

v1::OracleActionResponse Session::OracleAction() {
  v1::OracleActionRequest request;
  request.set_session_id(id());
  v1::OracleActionResponse response;
  Check("OracleAction", connection_->tasks().OracleAction(connection_->MakeContext().get(), request, &response));
  return response;
}

}  // namespace culinarycut::client
