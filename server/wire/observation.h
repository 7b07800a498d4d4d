// What the engine reports, on the wire: observations (robot, food, instruction, images), step
// results, session stats, telemetry frames and the CreateSession spec handshake.
#pragma once

#include <cstdint>
#include <string>

#include "culinarycut/v1/simulator.pb.h"
#include "sim/core/stage_timer.h"
#include "sim/world/model.h"
#include "sim/world/observation.h"
#include "sim/world/state.h"
#include "sim/world/step.h"

namespace culinarycut::server {

void StampToWire(std::uint64_t frame_id, double sim_time_s, v1::FrameStamp* wire);

// Throws render::RenderError when PNG/JPEG encoding of an image fails.
void ObservationToWire(const Model& model, const Observation& observation, v1::Observation* wire);

// Reward, termination, truncation, task score and the step's diagnostics (not the observation).
void StepResultToWire(const StepResult& result, double render_wall_time_ms, v1::StepResponse* wire);

// What the session has built and run, with its accumulated stage timings.
void SessionStatsToWire(const Model& model, const State& state, const StageTotals& totals, v1::SessionStats* wire);

// What the telemetry socket publishes for one session after a Reset, Step or Restore; `step_report`, the
// safety limiter's report of the Step that led to it (null otherwise), adds whether it acted and which guards bound.
v1::TelemetryFrame TelemetryToWire(const Observation& observation, const safety::LimiterReport* step_report = nullptr);

// The spec handshake of CreateSession: every observation array and every control mode's action.
void DescribeSpaces(const Model& model, v1::CreateSessionResponse* response);

}  // namespace culinarycut::server
