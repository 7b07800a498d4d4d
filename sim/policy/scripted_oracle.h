// The scripted oracle policy: instruction + observed object boxes -> parse -> plan -> one action
// per control step in the chosen control mode. The planning lives here, in C++; the server
// exposes it (Tasks.StartOracle / Tasks.OracleAction) so Python clients call the same logic.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/task/cut_planner.h"
#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"
#include "sim/world/control_mode.h"
#include "sim/world/model.h"

namespace culinarycut {

struct OracleConfig {
  std::string instruction;                // parsed into a CutSpec unless `spec` is given
  std::optional<task::CutSpec> spec;      // overrides the instruction
  std::vector<task::ObjectBox> objects;   // every object the oracle sees (world frame)
  std::string target_name;                // which object to cut; empty: the one of the spec's food
  ControlMode control_mode = kDefaultControlMode;
  task::PlannerOptions planner;
  std::uint64_t seed = 0;                 // drives the planner's sampled parameters
};

class ScriptedOracle {
 public:
  // Plans from the robot at rest at `qpos_rad` at sim time `now_s`. Throws task::TaskError for an
  // instruction it cannot parse, a target it cannot find or tell apart, or a plan it cannot make.
  ScriptedOracle(const Model& model, const OracleConfig& config, const Eigen::VectorXd& qpos_rad,
                 double now_s);

  // The action for the control step that starts at `now_s` with the robot at `qpos_rad`: it aims
  // at the planned TCP pose at the end of that step. After the plan ends it holds the last pose.
  Eigen::VectorXd Act(const Model& model, const Eigen::VectorXd& qpos_rad, double now_s) const;

  bool Finished(double now_s) const { return now_s - start_time_s_ >= trajectory_.duration_s(); }
  task::SegmentPhase PhaseAt(double now_s) const { return trajectory_.PhaseAt(now_s - start_time_s_); }

  const task::CutSpec& spec() const { return trajectory_.spec(); }
  const task::ObjectBox& target() const { return target_; }
  const task::CutTrajectory& trajectory() const { return trajectory_; }
  ControlMode control_mode() const { return control_mode_; }
  double start_time_s() const { return start_time_s_; }

 private:
  task::ObjectBox target_;
  task::CutTrajectory trajectory_;
  ControlMode control_mode_;
  double start_time_s_;
};

// The object `spec` asks for among `objects`: by `target_name` when given, else the only object of
// the spec's food. Throws task::TaskError naming what the scene holds when there is none or several.
const task::ObjectBox& FindTargetObject(const std::vector<task::ObjectBox>& objects,
                                        const task::CutSpec& spec, const std::string& target_name);

}  // namespace culinarycut
