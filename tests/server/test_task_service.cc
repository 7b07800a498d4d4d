// End to end: the Tasks service on a real server over a loopback socket, driven by the C++ client:
// instructions, planning, scoring and the scripted oracle running a whole cut on a session.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

#include "culinarycut/client.h"
#include "server/simulation_server.h"

using namespace culinarycut;
using namespace culinarycut::client;

namespace {

server::ServerOptions TestOptions() {
  server::ServerOptions options;
  options.listen_address = "127.0.0.1:0";
  options.telemetry_endpoint = "";
  options.max_sessions = 4;
  options.idle_timeout_s = 60;
  return options;
}

// A 0.20 m cucumber lying along y on the board, bottom on the board top (z = 0.02 m).
v1::ObjectBox CucumberBox() {
  v1::ObjectBox box;
  box.set_name("cucumber_0");
  box.set_food("cucumber");
  for (double value : {0.5, 0.02, 0.04}) box.mutable_pose()->add_position(value);
  const double half_angle = M_PI / 4;  // 90 deg about z: the box's x axis along world y
  for (double value : {std::cos(half_angle), 0.0, 0.0, std::sin(half_angle)}) {
    box.mutable_pose()->add_quaternion(value);
  }
  for (double value : {0.20, 0.04, 0.04}) box.add_extent_m(value);
  return box;
}

v1::ObjectBox AppleBox() {
  v1::ObjectBox box;
  box.set_name("apple_1");
  box.set_food("apple");
  for (double value : {0.45, -0.12, 0.06}) box.mutable_pose()->add_position(value);
  for (double value : {1.0, 0.0, 0.0, 0.0}) box.mutable_pose()->add_quaternion(value);
  for (double value : {0.08, 0.08, 0.08}) box.add_extent_m(value);
  return box;
}

std::pair<grpc::StatusCode, std::string> ErrorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const RpcError& error) {
    return {error.code(), error.what()};
  }
  return {grpc::StatusCode::OK, ""};
}

// Rotates (1, 0, 0), (0, 1, 0) or (0, 0, 1) by the quaternion at tcp_pose[3:7].
Eigen::Vector3d TcpAxis(const std::vector<double>& tcp_pose, int axis) {
  const Eigen::Quaterniond rotation(tcp_pose[3], tcp_pose[4], tcp_pose[5], tcp_pose[6]);
  return rotation.toRotationMatrix().col(axis);
}

}  // namespace

TEST_CASE("instructions parse to cut specs over the wire and bad ones name what is missing",
          "[server][tasks]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  const v1::ParseInstructionResponse parsed =
      client.ParseInstruction("Saw cut the cucumber at 0.3 ratio from the left side");
  CHECK(parsed.spec().style() == "saw");
  CHECK(parsed.spec().state() == "ratio");
  CHECK(parsed.spec().ratio() == Approx(0.3));
  CHECK(parsed.spec().reference() == "left");
  CHECK(parsed.spec().target_object() == "cucumber");
  REQUIRE(parsed.target_fractions_size() == 1);
  CHECK(parsed.target_fractions(0) == Approx(0.3));

  // Generated held-out instructions parse back to their spec over the wire too.
  v1::GenerateInstructionsRequest generate;
  *generate.mutable_spec() = parsed.spec();
  generate.set_seed(11);
  generate.set_count(6);
  generate.set_split("held_out");
  const std::vector<std::string> instructions = client.GenerateInstructions(generate);
  REQUIRE(instructions.size() == 6);
  for (const std::string& instruction : instructions) {
    INFO(instruction);
    const v1::CutSpec back = client.ParseInstruction(instruction).spec();
    CHECK(back.style() == "saw");
    CHECK(back.ratio() == Approx(0.3));
    CHECK(back.reference() == "left");
  }
  generate.set_split("validation");
  CHECK_THAT(ErrorOf([&] { client.GenerateInstructions(generate); }).second,
             Catch::Contains("use train, held_out or all"));

  const auto [code, message] = ErrorOf([&] { client.ParseInstruction("cut it at 0.3 ratio"); });
  CHECK(code == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(message, Catch::Contains("cucumber"));  // the message lists the foods it knows
}

TEST_CASE("a planned cut scores as a success, a cut on the wrong side does not", "[server][tasks]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  v1::PlanCutRequest request;
  request.set_instruction("cut the cucumber at 0.3 ratio from the right");
  *request.mutable_target() = CucumberBox();
  // Knife 0.3 m above the table, edge down (180 deg about world x).
  for (double value : {0.45, 0.0, 0.30}) request.mutable_start_tcp_pose()->add_position(value);
  for (double value : {0.0, 1.0, 0.0, 0.0}) request.mutable_start_tcp_pose()->add_quaternion(value);
  request.set_seed(7);
  request.set_sample_rate_hz(100);
  const v1::CutPlan plan = client.PlanCut(request);
  REQUIRE(plan.cuts_size() == 1);
  CHECK(plan.cuts(0).fraction_from_left() == Approx(0.7));
  CHECK(plan.duration_s() > 0.0);
  CHECK(plan.samples_size() == Approx(plan.duration_s() * 100).margin(2));

  // The blade plane at the deepest planned sample, scored as a measured cut.
  const v1::TrajectorySample* deepest = &plan.samples(0);
  for (const auto& sample : plan.samples()) {
    if (sample.tcp_pose().position(2) < deepest->tcp_pose().position(2)) deepest = &sample;
  }
  const std::vector<double> tcp(deepest->tcp_pose().position().begin(),
                                deepest->tcp_pose().position().end());
  std::vector<double> pose = tcp;
  pose.insert(pose.end(), deepest->tcp_pose().quaternion().begin(),
              deepest->tcp_pose().quaternion().end());
  v1::ScoreCutsRequest score_request;
  *score_request.mutable_spec() = plan.spec();
  *score_request.mutable_target() = CucumberBox();
  v1::MeasuredCut* cut = score_request.add_cuts();
  cut->set_object_name("cucumber_0");
  for (double value : tcp) cut->add_plane_point_m(value);
  for (int i = 0; i < 3; ++i) cut->add_plane_normal(TcpAxis(pose, 1)[i]);
  const v1::TaskScore score = client.ScoreCuts(score_request);
  CHECK(score.success());
  CHECK(score.required(0).position_error_fraction() < 0.005);

  score_request.mutable_spec()->set_reference("left");  // 0.3 from the left is 0.4 away
  const v1::TaskScore wrong_side = client.ScoreCuts(score_request);
  CHECK_FALSE(wrong_side.success());
  CHECK_THAT(wrong_side.summary(), Catch::Contains("off by 40.0%"));
}

TEST_CASE("the scripted oracle cuts through the target in every control mode", "[server][tasks][oracle]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  const std::string mode = GENERATE("pd_ee_delta_pose", "pd_ee_pose", "pd_ee_pose_quat", "pd_joint_pos", "pd_joint_delta_pos");
  auto session = client.CreateSession();
  session->Reset(3);

  v1::StartOracleRequest request;
  request.set_instruction("slice the cucumber at 0.3 ratio from the left side");
  *request.add_objects() = CucumberBox();
  *request.add_objects() = AppleBox();  // a second object: the oracle must pick the cucumber
  request.set_control_mode(mode);
  const v1::CutPlan plan = session->StartOracle(request);
  REQUIRE(plan.target_name() == "cucumber_0");
  REQUIRE(plan.cuts_size() == 1);
  const double cut_start_s = plan.cuts(0).start_time_s();
  const double cut_end_s = plan.cuts(0).end_time_s();
  const Eigen::Vector3d target(plan.cuts(0).target_point_m(0), plan.cuts(0).target_point_m(1),
                               plan.cuts(0).target_point_m(2));

  // Run the plan; during the cut, the blade plane must stay on the target and the edge go down.
  double worst_plane_distance_m = 0.0;
  double lowest_tcp_z_m = 1.0;
  std::vector<double> deepest_pose;
  int steps = 0;
  for (; steps < 2000; ++steps) {
    const v1::OracleActionResponse next = session->OracleAction();
    if (next.finished()) break;
    REQUIRE(next.action().control_mode() == mode);
    const StepResult result = session->Step(
        mode, {next.action().values().begin(), next.action().values().end()});
    const double t = result.observation.sim_time;
    const std::vector<double>& tcp = result.observation.tcp_pose;
    if (t > cut_start_s + 0.2 && t < cut_end_s) {
      const Eigen::Vector3d position(tcp[0], tcp[1], tcp[2]);
      worst_plane_distance_m =
          std::max(worst_plane_distance_m, std::abs((target - position).dot(TcpAxis(tcp, 1))));
    }
    if (tcp[2] < lowest_tcp_z_m) {
      lowest_tcp_z_m = tcp[2];
      deepest_pose = tcp;
    }
  }
  INFO("control mode " << mode << ", " << steps << " steps");
  CHECK(steps == Approx(plan.duration_s() / session->handshake().control_timestep()).margin(2));
  CHECK(worst_plane_distance_m < 0.002);
  CHECK(lowest_tcp_z_m < 0.02 + 0.002);  // the edge reached the object's bottom (board top)

  // Score the cut the knife actually made.
  v1::ScoreCutsRequest score_request;
  *score_request.mutable_spec() = plan.spec();
  *score_request.mutable_target() = CucumberBox();
  v1::MeasuredCut* cut = score_request.add_cuts();
  cut->set_object_name("cucumber_0");
  for (int i = 0; i < 3; ++i) cut->add_plane_point_m(deepest_pose[i]);
  for (int i = 0; i < 3; ++i) cut->add_plane_normal(TcpAxis(deepest_pose, 1)[i]);
  const v1::TaskScore score = client.ScoreCuts(score_request);
  INFO(score.summary());
  CHECK(score.success());
  CHECK(score.required(0).position_error_fraction() < 0.01);
}

TEST_CASE("oracle calls out of order or on bad input get clear errors", "[server][tasks][oracle]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  auto session = client.CreateSession();

  v1::StartOracleRequest request;
  request.set_instruction("cut the cucumber in half");
  *request.add_objects() = CucumberBox();
  auto [code, message] = ErrorOf([&] { session->StartOracle(request); });
  CHECK(code == grpc::StatusCode::FAILED_PRECONDITION);
  CHECK_THAT(message, Catch::Contains("call Reset"));

  session->Reset(0);
  std::tie(code, message) = ErrorOf([&] { session->OracleAction(); });
  CHECK(code == grpc::StatusCode::FAILED_PRECONDITION);
  CHECK_THAT(message, Catch::Contains("call StartOracle after Reset"));

  v1::StartOracleRequest no_banana = request;
  no_banana.set_instruction("cut the banana in half");
  std::tie(code, message) = ErrorOf([&] { session->StartOracle(no_banana); });
  CHECK(code == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(message, Catch::Contains("the scene has cucumber_0 (cucumber)"));

  v1::StartOracleRequest bad_mode = request;
  bad_mode.set_control_mode("pd_teleport");
  std::tie(code, message) = ErrorOf([&] { session->StartOracle(bad_mode); });
  CHECK(code == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(message, Catch::Contains("control_mode 'pd_teleport' is unknown"));

  v1::StartOracleRequest flat = request;
  flat.mutable_objects(0)->set_extent_m(2, 0.0);
  std::tie(code, message) = ErrorOf([&] { session->StartOracle(flat); });
  CHECK(code == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(message, Catch::Contains("extent"));

  // A good plan, then a failed StartOracle: the old plan must not run on silently.
  session->StartOracle(request);
  CHECK_FALSE(session->OracleAction().finished());
  CHECK(ErrorOf([&] { session->StartOracle(no_banana); }).first == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK(ErrorOf([&] { session->OracleAction(); }).first == grpc::StatusCode::FAILED_PRECONDITION);

  // A good plan, then Reset: the plan belonged to the old episode.
  session->StartOracle(request);
  CHECK_FALSE(session->OracleAction().finished());
  session->Reset(1);
  std::tie(code, message) = ErrorOf([&] { session->OracleAction(); });
  CHECK(code == grpc::StatusCode::FAILED_PRECONDITION);

  v1::StartOracleRequest unknown_session = request;
  v1::StartOracleResponse response;
  unknown_session.set_session_id("no-such-session");
  grpc::ClientContext context;
  const grpc::Status status = client.tasks_stub().StartOracle(&context, unknown_session, &response);
  CHECK(status.error_code() == grpc::StatusCode::NOT_FOUND);
}

TEST_CASE("a plan too long for one message at the asked rate is refused with advice", "[server][tasks]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  v1::PlanCutRequest request;
  request.set_instruction("guillotine cut the apple into five equal pieces");
  *request.mutable_target() = AppleBox();
  for (double value : {0.45, 0.0, 0.30}) request.mutable_start_tcp_pose()->add_position(value);
  for (double value : {0.0, 1.0, 0.0, 0.0}) request.mutable_start_tcp_pose()->add_quaternion(value);
  request.set_sample_rate_hz(1000);
  const auto [code, message] = ErrorOf([&] { client.PlanCut(request); });
  CHECK(code == grpc::StatusCode::INVALID_ARGUMENT);
  CHECK_THAT(message, Catch::Contains("lower sample_rate_hz"));
  request.set_sample_rate_hz(100);
  CHECK(client.PlanCut(request).cuts_size() == 4);
}

TEST_CASE("after RestoreSnapshot the oracle replays the same actions", "[server][tasks][oracle]") {
  server::SimulationServer server(TestOptions());
  Client client(server.address());
  auto session = client.CreateSession();
  session->Reset(5);
  v1::StartOracleRequest request;
  request.set_instruction("saw the cucumber into three pieces");
  *request.add_objects() = CucumberBox();
  session->StartOracle(request);
  auto run = [&](int steps) {
    std::vector<double> trace;
    for (int i = 0; i < steps; ++i) {
      const v1::OracleActionResponse next = session->OracleAction();
      const std::vector<double> values(next.action().values().begin(), next.action().values().end());
      trace.insert(trace.end(), values.begin(), values.end());
      const StepResult result = session->Step(next.action().control_mode(), values);
      trace.insert(trace.end(), result.observation.tcp_pose.begin(), result.observation.tcp_pose.end());
    }
    return trace;
  };
  run(40);
  const std::string snapshot = session->SaveSnapshot();
  const std::vector<double> first = run(60);
  session->RestoreSnapshot(snapshot);
  const std::vector<double> replay = run(60);
  CHECK(first == replay);  // bit for bit
}
