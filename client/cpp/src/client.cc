#include "culinarycut/client.h"

namespace culinarycut::client {
namespace {

constexpr char kFieldMetadataKey[] = "culinarycut-field";  // the server's structured field detail

// Runs one RPC with a fresh context; on failure throws RpcError with the server's field detail.
template <typename Rpc>
void Call(const char* method, const Connection& connection, Rpc rpc) {
  const std::unique_ptr<grpc::ClientContext> context = connection.MakeContext();
  const grpc::Status status = rpc(context.get());
  if (status.ok()) return;
  const auto& trailers = context->GetServerTrailingMetadata();
  const auto field = trailers.find(kFieldMetadataKey);
  throw RpcError(method, status,
                 field == trailers.end() ? std::string() : std::string(field->second.data(), field->second.size()));
}

}  // namespace

namespace {

// gRPC answers a request it cannot decode itself, before the server's code sees it, with INTERNAL and no
// message: said here, so that a client's bug does not read as an engine failure.
std::string Details(const grpc::Status& status) {
  if (status.error_code() == grpc::StatusCode::INTERNAL && status.error_message().empty()) {
    return "the server could not decode the request (gRPC answered INTERNAL with no message): it is not a valid "
           "culinarycut.v1 message, e.g. a string field that is not UTF-8; the request was not applied, and this "
           "is a fault in what the client sent, not in the engine";
  }
  const std::string& message = status.error_message();
  // A TCP connection the server closed as soon as it was made: it was at its connection caps, or stopping.
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE &&
      (message.find("Socket closed") != std::string::npos || message.find("Connection reset") != std::string::npos)) {
    return message + "; the server closed the connection: it may be at its connection caps (--max-connections, "
                     "--max-connections-per-address; docs/protocol.md) or shutting down";
  }
  return message;
}

}  // namespace

RpcError::RpcError(const std::string& method, const grpc::Status& status, std::string field)
    : std::runtime_error(method + " failed (gRPC code " + std::to_string(status.error_code()) + "): " +
                         Details(status)),
      code_(status.error_code()),
      details_(Details(status)),
      field_(std::move(field)) {}

namespace {

// Replies with camera images exceed gRPC's default 4 MB (three 640x480 RGB-D-segmentation views are 10 MB).
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& address, const ConnectionOptions& options) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(512 * 1024 * 1024);
  const bool tls = options.tls || !options.tls_root_certs_pem.empty() || !options.tls_client_cert_pem.empty() ||
                   !options.token.empty();
  if (!tls) return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments);
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = options.tls_root_certs_pem;
  ssl.pem_cert_chain = options.tls_client_cert_pem;
  ssl.pem_private_key = options.tls_client_key_pem;
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::SslCredentials(ssl);
  if (!options.token.empty()) {  // "authorization: Bearer <token>" on every call
    credentials = grpc::CompositeChannelCredentials(credentials, grpc::AccessTokenCredentials(options.token));
  }
  return grpc::CreateCustomChannel(address, credentials, arguments);
}

}  // namespace

Connection::Connection(const std::string& address, const ConnectionOptions& options)
    : channel_(MakeChannel(address, options)),
      simulator_(v1::Simulator::NewStub(channel_)),
      tasks_(v1::Tasks::NewStub(channel_)),
      call_timeout_(options.call_timeout) {}

std::unique_ptr<grpc::ClientContext> Connection::MakeContext() const {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() + call_timeout_);
  return context;
}

Client::Client(const std::string& address, std::chrono::milliseconds call_timeout)
    : Client(address, ConnectionOptions{call_timeout}) {}

Client::Client(const std::string& address, const ConnectionOptions& options)
    : connection_(std::make_shared<Connection>(address, options)) {}

bool Client::WaitForServer(std::chrono::milliseconds timeout) {
  return connection_->channel().WaitForConnected(std::chrono::system_clock::now() + timeout);
}

v1::ServerInfo Client::GetServerInfo() {
  v1::ServerInfo info;
  Call("GetServerInfo", *connection_, [&](grpc::ClientContext* context) {
    return stub().GetServerInfo(context, v1::GetServerInfoRequest(), &info);
  });
  return info;
}

std::unique_ptr<Session> Client::CreateSession(const v1::SceneSpec& scene) {
  v1::CreateSessionRequest request;
  *request.mutable_scene() = scene;
  v1::CreateSessionResponse response;
  Call("CreateSession", *connection_, [&](grpc::ClientContext* context) {
    return stub().CreateSession(context, request, &response);
  });
  return std::make_unique<Session>(connection_, std::move(response));
}

std::unique_ptr<Session> Client::AttachSession(const std::string& session_id) {
  v1::CreateSessionResponse handshake;
  handshake.set_session_id(session_id);
  return std::make_unique<Session>(connection_, std::move(handshake), /*owned=*/false);
}

v1::ParseInstructionResponse Client::ParseInstruction(const std::string& instruction) {
  v1::ParseInstructionRequest request;
  request.set_instruction(instruction);
  v1::ParseInstructionResponse response;
  Call("ParseInstruction", *connection_, [&](grpc::ClientContext* context) {
    return tasks_stub().ParseInstruction(context, request, &response);
  });
  return response;
}

std::vector<std::string> Client::GenerateInstructions(const v1::GenerateInstructionsRequest& request) {
  v1::GenerateInstructionsResponse response;
  Call("GenerateInstructions", *connection_, [&](grpc::ClientContext* context) {
    return tasks_stub().GenerateInstructions(context, request, &response);
  });
  return {response.instructions().begin(), response.instructions().end()};
}

v1::CutPlan Client::PlanCut(const v1::PlanCutRequest& request) {
  v1::PlanCutResponse response;
  Call("PlanCut", *connection_, [&](grpc::ClientContext* context) {
    return tasks_stub().PlanCut(context, request, &response);
  });
  return response.plan();
}

v1::TaskScore Client::ScoreCuts(const v1::ScoreCutsRequest& request) {
  v1::ScoreCutsResponse response;
  Call("ScoreCuts", *connection_, [&](grpc::ClientContext* context) {
    return tasks_stub().ScoreCuts(context, request, &response);
  });
  return response.score();
}

Session::Session(std::shared_ptr<Connection> connection, v1::CreateSessionResponse handshake, bool owned)
    : connection_(std::move(connection)), handshake_(std::move(handshake)), owned_(owned) {}

Session::~Session() {
  if (!owned_) return;
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
  Call("Reset", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().Reset(context, request, &response);
  });
  return FromWire(response.stamp(), response.observation());
}

StepResult Session::Step(const std::string& control_mode, const std::vector<double>& values) {
  v1::StepRequest request;
  request.set_session_id(id());
  request.mutable_action()->set_control_mode(control_mode);
  request.mutable_action()->mutable_values()->Assign(values.begin(), values.end());
  v1::StepResponse response;
  Call("Step", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().Step(context, request, &response);
  });
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
  Call("Observe", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().Observe(context, request, &response);
  });
  return FromWire(response.stamp(), response.observation());
}

std::string Session::SaveSnapshot() {
  v1::SaveSnapshotRequest request;
  request.set_session_id(id());
  v1::SaveSnapshotResponse response;
  Call("SaveSnapshot", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().SaveSnapshot(context, request, &response);
  });
  return response.snapshot();
}

Observation Session::RestoreSnapshot(const std::string& snapshot) {
  v1::RestoreSnapshotRequest request;
  request.set_session_id(id());
  request.set_snapshot(snapshot);
  v1::RestoreSnapshotResponse response;
  Call("RestoreSnapshot", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().RestoreSnapshot(context, request, &response);
  });
  return FromWire(response.stamp(), response.observation());
}

v1::SessionStats Session::GetSessionStats() {
  v1::GetSessionStatsRequest request;
  request.set_session_id(id());
  v1::SessionStats response;
  Call("GetSessionStats", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().GetSessionStats(context, request, &response);
  });
  return response;
}

void Session::Close() {
  if (closed_) return;
  closed_ = true;
  v1::CloseSessionRequest request;
  request.set_session_id(id());
  v1::CloseSessionResponse response;
  Call("CloseSession", *connection_, [&](grpc::ClientContext* context) {
    return connection_->simulator().CloseSession(context, request, &response);
  });
}

v1::CutPlan Session::StartOracle(v1::StartOracleRequest request) {
  request.set_session_id(id());
  v1::StartOracleResponse response;
  Call("StartOracle", *connection_, [&](grpc::ClientContext* context) {
    return connection_->tasks().StartOracle(context, request, &response);
  });
  return response.plan();
}

v1::OracleActionResponse Session::OracleAction() {
  v1::OracleActionRequest request;
  request.set_session_id(id());
  v1::OracleActionResponse response;
  Call("OracleAction", *connection_, [&](grpc::ClientContext* context) {
    return connection_->tasks().OracleAction(context, request, &response);
  });
  return response;
}

}  // namespace culinarycut::client
