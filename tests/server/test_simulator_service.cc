// End to end: a real server on a loopback port, driven by the C++ client library over gRPC.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <thread>

#include <unistd.h>

#include "culinarycut/client.h"
#include "server/simulation_server.h"

using namespace culinarycut;
using namespace culinarycut::client;

namespace {

server::ServerOptions TestOptions(std::uint32_t max_sessions = 8) {
  server::ServerOptions options;
  options.listen_address = "127.0.0.1:0";
  options.telemetry_endpoint = "";
  options.max_sessions = max_sessions;
  options.idle_timeout_s = 60;
  options.safety_model_path = CULINARYCUT_TEST_FORCE_MODEL;  // a hand-written test asset, not the fitted one
  return options;
}

double Distance(const std::vector<double>& a, const std::vector<double>& b) {
  return std::sqrt(std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) + std::pow(a[2] - b[2], 2));
}

// Angle (rad) between two unit quaternions (w, x, y, z) stored at offset 3 of 7-vectors.
double QuaternionAngle(const std::vector<double>& a, const std::vector<double>& b) {
  double dot = 0;
  for (int i = 3; i < 7; ++i) dot += a[i] * b[i];
  return 2 * std::acos(std::min(1.0, std::abs(dot)));
}

grpc::StatusCode CodeOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const RpcError& error) {
    return error.code();
  }
  return grpc::StatusCode::OK;
}

std::string MessageOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const RpcError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_CASE("server info reports version, capabilities, control modes and limits", "[server]") {
  server::SimulationServer server(TestOptions(3));
  Client client(server.address());
  const v1::ServerInfo info = client.GetServerInfo();
  CHECK(info.protocol() == "culinarycut.v1");
  CHECK_FALSE(info.version().empty());
  CHECK(info.control_modes_size() == 6);
  CHECK(info.limits().max_sessions() == 3);
}

TEST_CASE("the C++ client drives the knife to a target over the wire", "[server]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  auto session = client.CreateSession();
  CHECK(session->handshake().control_modes_size() == 6);
  CHECK(session->handshake().control_timestep() == Approx(0.05));
  const Observation start = session->Reset(0);
  REQUIRE(start.qpos.size() == 7);
  CHECK(start.frame_id == 0);

  const std::vector<double> target = {0.5, 0.05, 0.12, 0.0, 1.0, 0.0, 0.0};  // above the board, edge down
  Observation observation;
  for (int step = 0; step < 60; ++step) observation = session->Step("pd_ee_pose_quat", target).observation;
  CHECK(observation.frame_id == 60);
  CHECK(observation.sim_time == Approx(3.0));
  CHECK(Distance(observation.tcp_pose, target) < 1e-3);
  CHECK(QuaternionAngle(observation.tcp_pose, target) < M_PI / 180);
}

TEST_CASE("snapshot then restore reproduces the same trajectory exactly, over the wire", "[server]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  auto session = client.CreateSession();
  session->Reset(3);
  for (int i = 0; i < 5; ++i) session->Step("pd_ee_delta_pose", {0.1, 0.0, -0.1, 0.0, 0.0, 0.2});
  const std::string snapshot = session->SaveSnapshot();
  auto rollout = [&] {
    std::vector<std::vector<double>> trajectory;
    for (int i = 0; i < 20; ++i) {
      const Observation o = session->Step("pd_joint_delta_pos", {0.2, -0.1, 0.0, 0.3, 0.0, -0.2, 0.5}).observation;
      trajectory.push_back(o.qpos);
      trajectory.push_back(o.qvel);
    }
    return trajectory;
  };
  const auto first = rollout();
  const Observation restored = session->RestoreSnapshot(snapshot);
  CHECK(restored.frame_id == 5);
  CHECK(rollout() == first);
}

TEST_CASE("four concurrent sessions stay independent and equal seeds and actions agree", "[server]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  std::vector<std::unique_ptr<Session>> sessions;
  for (int i = 0; i < 4; ++i) sessions.push_back(client.CreateSession());
  std::vector<Observation> finals(4);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&, i] {
      sessions[i]->Reset(7);
      // Sessions 0 and 1 get the same actions; 2 and 3 move elsewhere.
      const double direction = i < 2 ? 1.0 : -1.0 * i;
      for (int step = 0; step < 30; ++step) {
        finals[i] = sessions[i]->Step("pd_ee_delta_pose", {0.0, 0.1 * direction, -0.05, 0.0, 0.0, 0.0}).observation;
      }
    });
  }
  for (auto& thread : threads) thread.join();
  CHECK(finals[0].qpos == finals[1].qpos);
  CHECK(finals[0].tcp_pose == finals[1].tcp_pose);
  CHECK(Distance(finals[0].tcp_pose, finals[2].tcp_pose) > 0.1);
  CHECK(Distance(finals[2].tcp_pose, finals[3].tcp_pose) > 0.05);
  // Session 0 replayed alone gives the same result as under concurrency.
  auto replay = client.CreateSession();
  replay->Reset(7);
  Observation alone;
  for (int step = 0; step < 30; ++step) alone = replay->Step("pd_ee_delta_pose", {0.0, 0.1, -0.05, 0.0, 0.0, 0.0}).observation;
  CHECK(alone.qpos == finals[0].qpos);
}

TEST_CASE("bad input gets a clear status and the server keeps serving", "[server][errors]") {
  server::SimulationServer server(TestOptions(2));
  Client client(server.address());
  auto session = client.CreateSession();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto still_serving = [&] { CHECK(session->Observe().qpos.size() == 7); };

  CHECK(CodeOf([&] { session->Step("pd_joint_delta_pos", std::vector<double>(7, 0.0)); }) ==
        grpc::StatusCode::FAILED_PRECONDITION);
  CHECK_THAT(MessageOf([&] { session->Observe(); }), Catch::Contains("Reset"));
  session->Reset(0);
  still_serving();

  v1::ObserveRequest unknown;
  unknown.set_session_id("s-000000000000");
  v1::ObserveResponse ignored;
  CHECK(client.stub().Observe(client.MakeContext().get(), unknown, &ignored).error_code() == grpc::StatusCode::NOT_FOUND);
  still_serving();

  CHECK(CodeOf([&] { session->Step("pd_joint_pos", {0.0, 0.0}); }) == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(MessageOf([&] { session->Step("pd_joint_pos", {0.0, 0.0}); }), Catch::Contains("action.values"));
  still_serving();
  CHECK_THAT(MessageOf([&] { session->Step("pd_joint_delta_pos", {0, nan, 0, 0, 0, 0, 0}); }),
             Catch::Contains("action.values[1]") && Catch::Contains("NaN"));
  still_serving();
  CHECK_THAT(MessageOf([&] { session->Step("pd_ee_delta_pose", {0, 0, inf, 0, 0, 0}); }),
             Catch::Contains("action.values[2]"));
  still_serving();
  CHECK_THAT(MessageOf([&] { session->Step("pd_ee_twist", {0, 0, 0, 0, 0, 0}); }), Catch::Contains("control_mode"));
  still_serving();
  CHECK(CodeOf([&] { session->Step("pd_ee_pose_quat", {0.5, 0, 0.2, 0, 0, 0, 0}); }) == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(MessageOf([&] { session->Step("pd_ee_pose_quat", {0.5, 0, 0.2, 0, 0, 0, 0}); }), Catch::Contains("quaternion"));
  still_serving();
  CHECK(CodeOf([&] { session->RestoreSnapshot("not a snapshot"); }) == grpc::StatusCode::INVALID_ARGUMENT);
  still_serving();

  auto second = client.CreateSession();
  CHECK(CodeOf([&] { client.CreateSession(); }) == grpc::StatusCode::RESOURCE_EXHAUSTED);
  second->Close();
  CHECK(client.CreateSession() != nullptr);
  still_serving();

  v1::SceneSpec bad_scene;
  bad_scene.mutable_robot()->set_physics_frequency_hz(333);
  CHECK_THAT(MessageOf([&] { client.CreateSession(bad_scene); }), Catch::Contains("physics_frequency_hz"));
  v1::SceneSpec food_scene;
  food_scene.add_objects()->set_food("banana");  // food without effects.mpm
  CHECK_THAT(MessageOf([&] { client.CreateSession(food_scene); }), Catch::Contains("effects.mpm"));
  v1::SceneSpec limiter_scene;
  limiter_scene.mutable_effects()->set_safety_limiter(true);
  CHECK(CodeOf([&] { client.CreateSession(limiter_scene); }) == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(MessageOf([&] { client.CreateSession(limiter_scene); }), Catch::Contains("effects.safety_limiter needs food"));
  still_serving();
}

TEST_CASE("a session whose client vanished is reclaimed after the idle timeout", "[server]") {
  server::ServerOptions options = TestOptions();
  options.idle_timeout_s = 0.3;
  server::SimulationServer server(options);
  Client client(server.address());
  auto session = client.CreateSession();
  session->Reset(0);
  CHECK(client.GetServerInfo().limits().active_sessions() == 1);
  std::this_thread::sleep_for(std::chrono::milliseconds(900));  // timeout + reaper period, with margin
  CHECK(client.GetServerInfo().limits().active_sessions() == 0);
  CHECK(CodeOf([&] { session->Observe(); }) == grpc::StatusCode::NOT_FOUND);
}

TEST_CASE("the server also listens on a Unix domain socket", "[server]") {
  server::ServerOptions options = TestOptions();
  const std::string path = "/tmp/culinarycut-test-" + std::to_string(::getpid()) + ".sock";
  options.listen_address = "unix://" + path;
  server::SimulationServer server(options);
  CHECK(server.address() == options.listen_address);
  Client client(server.address());
  auto session = client.CreateSession();
  CHECK(session->Reset(0).qpos.size() == 7);
}
