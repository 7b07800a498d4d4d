// A Step the engine fails half-way (here: a particle made NaN inside the session, as a blown-up
// simulation would leave it) reaches the client as INTERNAL with the engine's reason; the session is
// then broken, refusing Step, Observe and SaveSnapshot with FAILED_PRECONDITION until Reset or
// RestoreSnapshot. Through a real server on loopback, with the generated stub (no client library).
#include <catch2/catch.hpp>

#include <limits>

#include <grpcpp/grpcpp.h>

#include "culinarycut/v1/simulator.grpc.pb.h"
#include "server/simulation_server.h"

using namespace culinarycut;

namespace {

struct Call {
  grpc::Status status;
  v1::StepResponse step;
};

v1::StepRequest HoldStill(const std::string& session_id) {
  v1::StepRequest request;
  request.set_session_id(session_id);
  request.mutable_action()->set_control_mode("pd_joint_delta_pos");
  for (int i = 0; i < 7; ++i) request.mutable_action()->add_values(0.0);
  return request;
}

}  // namespace

TEST_CASE("a Step the engine fails breaks the session until Reset or RestoreSnapshot", "[server][errors]") {
  server::ServerOptions options;
  options.listen_address = "127.0.0.1:0";
  options.telemetry_endpoint = "";
  server::SimulationServer server(options);
  auto stub = v1::Simulator::NewStub(grpc::CreateChannel(server.address(), grpc::InsecureChannelCredentials()));

  v1::CreateSessionRequest create;
  v1::SceneSpec& scene = *create.mutable_scene();
  scene.set_quality("draft");
  scene.mutable_effects()->set_mpm(true);
  scene.mutable_effects()->set_damage(true);
  scene.mutable_effects()->set_topology(true);
  scene.add_objects()->set_food("cucumber");
  v1::CreateSessionResponse created;
  {
    grpc::ClientContext context;
    REQUIRE(stub->CreateSession(&context, create, &created).ok());
  }
  const std::string id = created.session_id();
  auto reset = [&] {
    grpc::ClientContext context;
    v1::ResetRequest request;
    request.set_session_id(id);
    v1::ResetResponse response;
    return stub->Reset(&context, request, &response);
  };
  auto step = [&] {
    grpc::ClientContext context;
    v1::StepResponse response;
    const grpc::Status status = stub->Step(&context, HoldStill(id), &response);
    return Call{status, response};
  };
  auto save = [&](std::string* snapshot) {
    grpc::ClientContext context;
    v1::SaveSnapshotRequest request;
    request.set_session_id(id);
    v1::SaveSnapshotResponse response;
    const grpc::Status status = stub->SaveSnapshot(&context, request, &response);
    if (snapshot) *snapshot = response.snapshot();
    return status;
  };
  auto observe = [&] {
    grpc::ClientContext context;
    v1::ObserveRequest request;
    request.set_session_id(id);
    v1::ObserveResponse response;
    return stub->Observe(&context, request, &response);
  };
  // One particle's position becomes NaN and the food is awake: the next substep must refuse it.
  auto run_away = [&] {
    server::SessionLock lock(*server.sessions().Find(id, ""));
    FoodState& food = *server.sessions().Find(id, "")->state.food;
    food.solver->particles().position[2][0] = std::numeric_limits<float>::quiet_NaN();
    food.awake = true;
  };

  REQUIRE(reset().ok());
  std::string good;
  REQUIRE(save(&good).ok());
  run_away();
  const Call failed = step();
  CHECK(failed.status.error_code() == grpc::StatusCode::INTERNAL);
  CHECK_THAT(failed.status.error_message(), Catch::Contains("broken") && Catch::Contains("NaN"));

  CHECK(step().status.error_code() == grpc::StatusCode::FAILED_PRECONDITION);
  CHECK_THAT(step().status.error_message(), Catch::Contains("is broken") && Catch::Contains("Reset"));
  CHECK(observe().error_code() == grpc::StatusCode::FAILED_PRECONDITION);
  CHECK(save(nullptr).error_code() == grpc::StatusCode::FAILED_PRECONDITION);

  {  // RestoreSnapshot recovers.
    grpc::ClientContext context;
    v1::RestoreSnapshotRequest request;
    request.set_session_id(id);
    request.set_snapshot(good);
    v1::RestoreSnapshotResponse response;
    REQUIRE(stub->RestoreSnapshot(&context, request, &response).ok());
  }
  const Call recovered = step();
  REQUIRE(recovered.status.ok());
  CHECK(recovered.step.stamp().frame_id() == 1);

  run_away();  // and so does Reset
  CHECK(step().status.error_code() == grpc::StatusCode::INTERNAL);
  REQUIRE(reset().ok());
  CHECK(step().status.ok());
}
