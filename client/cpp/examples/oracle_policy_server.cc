// Example: a policy written in C++, served over the policy protocol (proto/culinarycut/v1/policy.proto)
// so that the benchmark runner plays whole suites with it:
//
//   oracle_policy_server --listen 127.0.0.1:50070 &
//   culinarycut bench run smoke --policy grpc --policy-url 127.0.0.1:50070
//
// The policy is the scripted oracle. It plans on the simulator (Tasks.StartOracle, through the C++
// client library), so its metadata asks for the episode's session; the runner then lends it the
// server's address, the session id and the bearer token in ResetPolicy. A policy that acts on the
// observation alone would leave needs_session false and read PolicyActRequest.observation instead.
//
// Usage: oracle_policy_server [--listen HOST:PORT] [--simulator-ca FILE]
//   --listen        where to serve (default 127.0.0.1:0: a free port, printed on the first line)
//   --simulator-ca  the CA of a simulator that uses TLS (default: the system's roots)
#include <grpcpp/grpcpp.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>

#include "culinarycut/client.h"
#include "culinarycut/v1/policy.grpc.pb.h"

namespace {

using culinarycut::client::Client;
using culinarycut::client::ConnectionOptions;
using culinarycut::client::RpcError;
using culinarycut::client::Session;
namespace v1 = culinarycut::v1;

constexpr char kControlMode[] = "pd_ee_pose_quat";  // TCP position (m) and orientation (w, x, y, z)
constexpr int kActionDim = 7;
constexpr std::size_t kMaxEpisodes = 64;  // episodes remembered at once (a runner plays a few in parallel)

// One episode's link to the simulator: the session the runner lent, planned on at ResetPolicy.
struct Episode {
  std::unique_ptr<Client> client;
  std::unique_ptr<Session> session;
};

// A float64 tensor of `values` (the protocol's bytes are little-endian, as on every machine this builds for).
v1::Tensor Float64Tensor(const google::protobuf::RepeatedField<double>& values) {
  v1::Tensor tensor;
  tensor.set_dtype("float64");
  tensor.add_shape(static_cast<std::uint32_t>(values.size()));
  tensor.set_data(std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double)));
  return tensor;
}

// A simulator call's failure as the policy's answer: the runner stores it as the episode's policy_error.
grpc::Status FromRpcError(const RpcError& error) {
  return grpc::Status(grpc::StatusCode::UNAVAILABLE, std::string("the simulator refused: ") + error.what());
}

class OraclePolicy final : public v1::Policy::Service {
 public:
  explicit OraclePolicy(std::string simulator_ca_pem) : simulator_ca_pem_(std::move(simulator_ca_pem)) {}

  grpc::Status GetPolicyMetadata(grpc::ServerContext*, const v1::PolicyMetadataRequest*,
                                 v1::PolicyMetadata* metadata) override {
    metadata->set_name("oracle-cpp");
    metadata->set_version("1");
    metadata->set_control_mode(kControlMode);
    metadata->set_action_dim(kActionDim);
    metadata->set_chunk_size(1);
    metadata->set_rate_hz(0.0);  // it follows the server's control rate
    metadata->set_needs_session(true);
    return grpc::Status::OK;
  }

  grpc::Status ResetPolicy(grpc::ServerContext*, const v1::PolicyResetRequest* request,
                           v1::PolicyResetResponse*) override {
    if (request->episode_id().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "episode_id is empty");
    }
    const v1::SimulatorSession& lent = request->session();
    if (lent.address().empty() || lent.session_id().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "session: the oracle plans on the simulator and needs its address and session id");
    }
    ConnectionOptions options;
    options.tls = lent.tls();
    options.tls_root_certs_pem = simulator_ca_pem_;
    options.token = lent.token();
    Episode episode;
    try {
      episode.client = std::make_unique<Client>(lent.address(), options);
      episode.session = episode.client->AttachSession(lent.session_id());
      v1::StartOracleRequest start;  // the scene's task and food objects, the episode's seed
      start.set_instruction(request->instruction());
      start.set_control_mode(kControlMode);
      start.mutable_seed()->set_value(request->seed());
      episode.session->StartOracle(start);
    } catch (const RpcError& error) {
      return FromRpcError(error);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (episodes_.size() >= kMaxEpisodes) episodes_.erase(episodes_.begin());  // a runner that never finished them
    episodes_[request->episode_id()] = std::make_shared<Episode>(std::move(episode));
    return grpc::Status::OK;
  }

  grpc::Status Act(grpc::ServerContext*, const v1::PolicyActRequest* request, v1::PolicyActResponse* response) override {
    std::shared_ptr<Episode> episode;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto found = episodes_.find(request->episode_id());
      if (found == episodes_.end()) {
        return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                            "Act for episode '" + request->episode_id() + "', which no ResetPolicy started");
      }
      episode = found->second;
    }
    v1::OracleActionResponse action;
    try {
      action = episode->session->OracleAction();  // the server reads the robot's state itself
    } catch (const RpcError& error) {
      return FromRpcError(error);
    }
    *response->mutable_actions() = Float64Tensor(action.action().values());
    response->set_control_mode(action.action().control_mode());
    response->set_finished(action.finished());
    if (action.finished()) {
      std::lock_guard<std::mutex> lock(mutex_);
      episodes_.erase(request->episode_id());
    }
    return grpc::Status::OK;
  }

 private:
  const std::string simulator_ca_pem_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Episode>> episodes_;
};

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot read " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

int Usage(const char* problem) {
  std::fprintf(stderr, "oracle_policy_server: %s\nusage: oracle_policy_server [--listen HOST:PORT] "
                       "[--simulator-ca FILE]\n", problem);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string listen = "127.0.0.1:0";
  std::string simulator_ca_pem;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if ((flag == "--listen" || flag == "--simulator-ca") && i + 1 >= argc) return Usage((flag + " needs a value").c_str());
    if (flag == "--listen") {
      listen = argv[++i];
    } else if (flag == "--simulator-ca") {
      try {
        simulator_ca_pem = ReadFile(argv[++i]);
      } catch (const std::exception& error) {
        return Usage(error.what());
      }
    } else {
      return Usage(("unknown option " + flag).c_str());
    }
  }
  // SIGINT and SIGTERM are waited for below; block them before gRPC starts its threads so none of them takes one.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  OraclePolicy policy(simulator_ca_pem);
  int port = 0;
  grpc::ServerBuilder builder;
  builder.AddListeningPort(listen, grpc::InsecureServerCredentials(), &port);  // serve on loopback: see the docs
  builder.RegisterService(&policy);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) return Usage(("cannot listen on " + listen).c_str());
  const std::string host = listen.substr(0, listen.rfind(':'));
  std::printf("serving policy oracle-cpp 1 (%s, needs the session) on %s:%d\n", kControlMode, host.c_str(), port);
  std::fflush(stdout);

  int signal = 0;
  sigwait(&stop_signals, &signal);
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
  return 0;
}
