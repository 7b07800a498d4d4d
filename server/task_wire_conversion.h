// Translation between the culinarycut.v1 task messages and sim/task's structs. Readers throw
// task::TaskError naming the field at fault; the service turns that into INVALID_ARGUMENT.
#pragma once

#include <string>
#include <vector>

#include "culinarycut/v1/task.pb.h"
#include "sim/task/cut_planner.h"
#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"
#include "sim/task/success_metrics.h"

namespace culinarycut::server {

task::CutSpec CutSpecFromWire(const v1::CutSpec& wire);
void CutSpecToWire(const task::CutSpec& spec, v1::CutSpec* wire);

// `field` names the message in errors, e.g. "objects[2]".
task::ObjectBox ObjectBoxFromWire(const v1::ObjectBox& wire, const std::string& field);
// A pose with a 3-vector position and a quaternion of positive norm (normalised here).
Eigen::Isometry3d PoseFromWire(const v1::Pose& wire, const std::string& field);
void PoseToWire(const Eigen::Isometry3d& pose, v1::Pose* wire);

task::PlannerOptions PlannerOptionsFromWire(const v1::PlannerOptions& wire);
task::SuccessTolerances TolerancesFromWire(const v1::SuccessTolerances& wire);
task::MeasuredCut MeasuredCutFromWire(const v1::MeasuredCut& wire, const std::string& field);

// The plan with samples at `sample_rate_hz` (0 = no samples).
void CutPlanToWire(const task::CutTrajectory& trajectory, const std::string& target_name,
                   double sample_rate_hz, v1::CutPlan* wire);
void TaskScoreToWire(const task::TaskScore& score, v1::TaskScore* wire);

}  // namespace culinarycut::server
