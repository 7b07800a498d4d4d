// The culinarycut.v1.Tasks gRPC service: the task logic of sim/task and the scripted oracle of
// sim/policy, for clients in any language. Stateless calls need no session; the oracle calls
// run on a session's robot under that session's lock.
#pragma once

#include "culinarycut/v1/task.grpc.pb.h"
#include "server/session_manager.h"

namespace culinarycut::server {

class TaskService final : public v1::Tasks::Service {
 public:
  explicit TaskService(SessionManager* sessions);

  grpc::Status ParseInstruction(grpc::ServerContext*, const v1::ParseInstructionRequest*,
                                v1::ParseInstructionResponse*) override;
  grpc::Status GenerateInstructions(grpc::ServerContext*, const v1::GenerateInstructionsRequest*,
                                    v1::GenerateInstructionsResponse*) override;
  grpc::Status PlanCut(grpc::ServerContext*, const v1::PlanCutRequest*, v1::PlanCutResponse*) override;
  grpc::Status ScoreCuts(grpc::ServerContext*, const v1::ScoreCutsRequest*,
                         v1::ScoreCutsResponse*) override;
  grpc::Status StartOracle(grpc::ServerContext*, const v1::StartOracleRequest*,
                           v1::StartOracleResponse*) override;
  grpc::Status OracleAction(grpc::ServerContext*, const v1::OracleActionRequest*,
                            v1::OracleActionResponse*) override;

 private:
  SessionManager* sessions_;
};

}  // namespace culinarycut::server
