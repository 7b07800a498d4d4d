// Drives a real server through the installed C++ client: server info, a session, reset, a step,
// an observation with the wrist wrench, session stats, close. Exit 0 only if every check holds.
#include <cstdio>
#include <string>

#include <culinarycut/client.h>

namespace {
int failures = 0;
void Expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "consumer: FAILED: %s\n", what);
    ++failures;
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer HOST:PORT\n");
    return 2;
  }
  try {
    culinarycut::client::Client client(argv[1]);
    Expect(client.WaitForServer(std::chrono::seconds(10)), "the server answers");
    Expect(client.GetServerInfo().protocol() == "culinarycut.v1", "the protocol is culinarycut.v1");
    auto session = client.CreateSession();
    const culinarycut::client::Observation start = session->Reset(/*seed=*/0);
    Expect(start.frame_id == 0 && start.qpos.size() == 7, "reset gives frame 0 and 7 joints");
    const culinarycut::client::StepResult step = session->Step("pd_ee_delta_pose", {0.0, 0.0, -0.1, 0.0, 0.0, 0.0});
    Expect(step.observation.frame_id == 1, "a step advances the frame");
    Expect(step.observation.wrist_wrench.size() == 6, "the wrist wrench has 6 values");
    Expect(!step.task_score.has_value() && !step.success, "no task, no score");
    Expect(session->GetSessionStats().stage_calls().at("physics") == 1, "session stats count the step");
    try {
      session->Step("pd_no_such_mode", {});
      Expect(false, "an unknown mode is refused");
    } catch (const culinarycut::client::RpcError& error) {
      Expect(error.code() == grpc::StatusCode::INVALID_ARGUMENT &&
                 error.details().find("action.control_mode") != std::string::npos,
             "an unknown mode is INVALID_ARGUMENT naming action.control_mode");
    }
    session->Close();
  } catch (const std::exception& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 1;
  }
  std::printf("consumer: %s\n", failures == 0 ? "all checks passed" : "some checks failed");
  return failures == 0 ? 0 : 1;
}
