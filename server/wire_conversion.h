// Translation between the wire messages (culinarycut.v1) and the engine's plain structs.
#pragma once

#include <string>

#include <grpcpp/grpcpp.h>

#include "culinarycut/v1/simulator.pb.h"
#include "sim/world/model.h"
#include "sim/world/observation.h"
#include "sim/world/state.h"

namespace culinarycut::server {

// Reads a SceneSpec. INVALID_ARGUMENT for malformed fields, UNIMPLEMENTED for features this
// server does not have yet; each message names the field.
grpc::Status SceneFromWire(const v1::SceneSpec& wire, SceneConfig* config);

// The scene with every default filled in, as the client should record it.
v1::SceneSpec SceneToWire(const SceneConfig& config);
// Fills in what the food model resolved: each object's pose and the MPM resolution.
void ResolvedFoodToWire(const FoodModel& food, v1::SceneSpec* wire);

void ObservationToWire(const RobotObservation& observation, v1::Observation* wire);
// The food part of an observation (pieces, contact); nothing for a scene without food.
void FoodObservationToWire(const State& state, v1::Observation* wire);
// What the session has built and run.
void SessionStatsToWire(const Model& model, const State& state, v1::SessionStats* wire);
void StampToWire(std::uint64_t frame_id, double sim_time_s, v1::FrameStamp* wire);

// What the telemetry socket publishes for one session after a Reset, Step or Restore.
v1::TelemetryFrame TelemetryToWire(const std::string& session_id, const RobotObservation& observation);

// The spec handshake of CreateSession: every observation array and every control mode's action.
void DescribeSpaces(const Model& model, v1::CreateSessionResponse* response);

}  // namespace culinarycut::server
