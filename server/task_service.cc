#include "server/task_service.h"

#include <type_traits>

#include <spdlog/spdlog.h>

#include "server/status.h"
#include "server/wire/action.h"
#include "server/wire/observation.h"
#include "server/wire/task.h"
#include "server/wire/values.h"
#include "sim/core/pose.h"
#include "sim/robot/kinematics.h"
#include "sim/task/instruction_generator.h"
#include "sim/task/instruction_parser.h"

namespace culinarycut::server {
namespace {

constexpr std::uint32_t kDefaultInstructionCount = 5;
constexpr std::uint32_t kMaxInstructionCount = 10000;
constexpr double kDefaultPlanSampleRateHz = 20.0;
constexpr double kMaxPlanSampleRateHz = 1000.0;

// Runs `body`, turning every exception into its status (status.h).
template <typename Body>
grpc::Status RunTask(Body&& body) {
  return Guarded([&] {
    body();
    return grpc::Status::OK;
  });
}

task::LanguageSplit LanguageSplitFromName(const std::string& name) {
  if (name.empty() || name == "train") return task::LanguageSplit::kTrain;
  if (name == "held_out") return task::LanguageSplit::kHeldOut;
  if (name == "all") return task::LanguageSplit::kAll;
  throw FieldError("split", "'" + name.substr(0, 64) + "' is unknown; use train, held_out or all");
}

double SampleRateFromWire(double rate_hz, double default_hz) {
  if (rate_hz == 0.0) return default_hz;
  if (!(rate_hz > 0.0 && rate_hz <= kMaxPlanSampleRateHz)) {
    throw FieldError("sample_rate_hz", "must be in (0, 1000] Hz (0 means the default)");
  }
  return rate_hz;
}

// The parser's errors name the request's instruction field.
task::CutSpec ParseInstructionField(const std::string& instruction) {
  task::CutSpec spec;
  CheckField("instruction", [&] { spec = task::ParseInstruction(instruction); });
  return spec;
}

// The spec of a request that carries either an instruction or a spec.
template <typename Request>
task::CutSpec SpecFromRequest(const Request& request) {
  switch (request.task_case()) {
    case Request::kInstruction:
      return ParseInstructionField(request.instruction());
    case Request::kSpec:
      return CutSpecFromWire(request.spec(), "spec");
    default:
      throw FieldError::WithMessage(
          "instruction", std::is_same_v<Request, v1::StartOracleRequest>
                             ? "give instruction (text) or spec (a CutSpec), or declare scene.task in the session's scene"
                             : "give either instruction (text) or spec (a CutSpec)");
  }
}

}  // namespace

TaskService::TaskService(SessionManager* sessions) : sessions_(sessions) {}

grpc::Status TaskService::ParseInstruction(grpc::ServerContext* context,
                                           const v1::ParseInstructionRequest* request,
                                           v1::ParseInstructionResponse* response) {
  return RunTask([&] {
    const task::CutSpec spec = ParseInstructionField(request->instruction());
    CutSpecToWire(spec, response->mutable_spec());
    response->set_description(task::Describe(spec));
    for (double fraction : task::TargetFractionsFromLeft(spec)) response->add_target_fractions(fraction);
  });
}

grpc::Status TaskService::GenerateInstructions(grpc::ServerContext* context,
                                               const v1::GenerateInstructionsRequest* request,
                                               v1::GenerateInstructionsResponse* response) {
  return RunTask([&] {
    const std::uint32_t count = request->count() == 0 ? kDefaultInstructionCount : request->count();
    if (count > kMaxInstructionCount) {
      throw FieldError("count", std::to_string(count) + " is above the limit of " + std::to_string(kMaxInstructionCount));
    }
    const task::CutSpec spec = CutSpecFromWire(request->spec(), "spec");
    for (const std::string& instruction :
         task::GenerateInstructions(spec, request->seed(), static_cast<int>(count),
                                    LanguageSplitFromName(request->split()))) {
      response->add_instructions(instruction);
    }
  });
}

grpc::Status TaskService::PlanCut(grpc::ServerContext* context, const v1::PlanCutRequest* request,
                                  v1::PlanCutResponse* response) {
  return RunTask([&] {
    const task::CutSpec spec = SpecFromRequest(*request);
    if (!request->has_target()) throw FieldError("target", "is missing: give the object's box");
    const task::ObjectBox target = ObjectBoxFromWire(request->target(), "target");
    if (!request->has_start_tcp_pose()) {
      throw FieldError("start_tcp_pose", "is missing: give the knife's current TCP pose");
    }
    const Eigen::Isometry3d start = PoseFromWire(request->start_tcp_pose(), "start_tcp_pose");
    const double rate_hz = SampleRateFromWire(request->sample_rate_hz(), kDefaultPlanSampleRateHz);
    const task::CutTrajectory trajectory = task::PlanCutTrajectory(
        target, spec, start, PlannerOptionsFromWire(request->options(), "options"), request->seed());
    CutPlanToWire(trajectory, target.name, rate_hz, response->mutable_plan());
  });
}

grpc::Status TaskService::ScoreCuts(grpc::ServerContext* context, const v1::ScoreCutsRequest* request,
                                    v1::ScoreCutsResponse* response) {
  return RunTask([&] {
    const task::CutSpec spec = CutSpecFromWire(request->spec(), "spec");
    if (!request->has_target()) throw FieldError("target", "is missing: give the object's box");
    const task::ObjectBox target = ObjectBoxFromWire(request->target(), "target");
    std::vector<task::MeasuredCut> cuts;
    for (int i = 0; i < request->cuts_size(); ++i) {
      cuts.push_back(MeasuredCutFromWire(request->cuts(i), "cuts[" + std::to_string(i) + "]"));
    }
    TaskScoreToWire(task::ScoreCuts(target, spec, cuts, TolerancesFromWire(request->tolerances(), "tolerances")),
                    response->mutable_score());
  });
}

grpc::Status TaskService::StartOracle(grpc::ServerContext* context, const v1::StartOracleRequest* request,
                                      v1::StartOracleResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) {
    return status;
  }
  SessionLock lock(*session);
  if (!session->state.has_been_reset()) return NotReset(*session);
  // A client that ignores a failed StartOracle must not go on running the previous plan.
  session->oracle.reset();
  const Model& model = *session->model;
  return RunTask([&] {
    OracleConfig config;
    // Without instruction or spec the oracle does the scene's own task, on its target object.
    const bool scene_task = request->task_case() == v1::StartOracleRequest::TASK_NOT_SET && model.task;
    config.spec = scene_task ? model.task->spec : SpecFromRequest(*request);
    for (int i = 0; i < request->objects_size(); ++i) {
      config.objects.push_back(
          ObjectBoxFromWire(request->objects(i), "objects[" + std::to_string(i) + "]"));
    }
    // Without objects in the request, the oracle sees the scene's own food at rest.
    if (config.objects.empty() && session->model->food) config.objects = session->model->food->objects;
    config.target_name = request->target_name();
    if (scene_task && config.target_name.empty() && request->objects_size() == 0) {
      config.target_name = model.food->objects[static_cast<std::size_t>(model.task->target_object)].name;
    }
    if (!request->control_mode().empty()) {
      config.control_mode = ControlModeFromWire(request->control_mode(), "control_mode");
    }
    config.planner = PlannerOptionsFromWire(request->options(), "options");
    config.seed = request->has_seed() ? request->seed().value() : session->state.seed;
    const double rate_hz =
        SampleRateFromWire(request->sample_rate_hz(), 1.0 / model.control_timestep_s);

    ScriptedOracle oracle(model, config, session->state.physics->JointPositions(),
                          session->state.sim_time_s);
    CutPlanToWire(oracle.trajectory(), oracle.target().name, rate_hz, response->mutable_plan());
    StampToWire(session->state.frame_id, session->state.sim_time_s, response->mutable_stamp());
    spdlog::info("session {}: oracle planned {} on {} ({:.2f} s)", session->id,
                 task::Describe(oracle.spec()), oracle.target().name,
                 oracle.trajectory().duration_s());
    session->oracle.emplace(std::move(oracle));
  });
}

grpc::Status TaskService::OracleAction(grpc::ServerContext* context, const v1::OracleActionRequest* request,
                                       v1::OracleActionResponse* response) {
  std::shared_ptr<Session> session;
  if (grpc::Status status = FindSession(sessions_, *context, request->session_id(), &session); !status.ok()) {
    return status;
  }
  SessionLock lock(*session);
  if (!session->oracle) {
    return MakeStatus(grpc::StatusCode::FAILED_PRECONDITION,
                        "session " + session->id +
                            " has no oracle plan for this episode; call StartOracle after Reset");
  }
  const ScriptedOracle& oracle = *session->oracle;
  const double now_s = session->state.sim_time_s;
  const Eigen::VectorXd action =
      oracle.Act(*session->model, session->state.physics->JointPositions(), now_s);
  response->mutable_action()->set_control_mode(ControlModeName(oracle.control_mode()));
  for (int i = 0; i < action.size(); ++i) response->mutable_action()->add_values(action[i]);
  response->set_finished(oracle.Finished(now_s));
  response->set_phase(task::Name(oracle.PhaseAt(now_s)));
  StampToWire(session->state.frame_id, now_s, response->mutable_stamp());
  return grpc::Status::OK;
}

}  // namespace culinarycut::server
