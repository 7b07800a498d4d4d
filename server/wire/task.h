// Translation between the culinarycut.v1 task messages and sim/task's structs. Readers throw
// FieldError naming the field at fault (and sim/task's own checks throw task::TaskError); the
// services turn both into INVALID_ARGUMENT (status.h). `field` is the message's path in errors.
#pragma once

#include <string>
#include <vector>

#include "culinarycut/v1/task.pb.h"
#include "sim/task/cut_planner.h"
#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"
#include "sim/task/success_metrics.h"

namespace culinarycut::server {

task::CutSpec CutSpecFromWire(const v1::CutSpec& wire, const std::string& field);
void CutSpecToWire(const task::CutSpec& spec, v1::CutSpec* wire);

task::ObjectBox ObjectBoxFromWire(const v1::ObjectBox& wire, const std::string& field);

task::PlannerOptions PlannerOptionsFromWire(const v1::PlannerOptions& wire, const std::string& field);
task::SuccessTolerances TolerancesFromWire(const v1::SuccessTolerances& wire, const std::string& field);
task::MeasuredCut MeasuredCutFromWire(const v1::MeasuredCut& wire, const std::string& field);

// The plan with samples at `sample_rate_hz` (0 = no samples).
void CutPlanToWire(const task::CutTrajectory& trajectory, const std::string& target_name,
                   double sample_rate_hz, v1::CutPlan* wire);
void TaskScoreToWire(const task::TaskScore& score, v1::TaskScore* wire);

}  // namespace culinarycut::server
