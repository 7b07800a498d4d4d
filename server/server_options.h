// What culinarycut-server is started with (see `culinarycut-server --help`).
#pragma once

#include <cstdint>
#include <string>

#include "server/access_control.h"
#include "server/connection_gate.h"

namespace culinarycut::server {

struct ServerOptions {
  std::string listen_address = "127.0.0.1:50051";   // port 0 picks a free port
  std::string telemetry_endpoint;                   // ZeroMQ PUB endpoint; empty (the default): telemetry off
  std::uint32_t max_sessions = 16;
  std::uint32_t max_sessions_per_owner = 0;          // one token's or certificate's sessions; 0: max_sessions
  double idle_timeout_s = 300.0;                     // sessions untouched this long are closed
  std::string robot_urdf_path;                       // empty: the shipped Panda with knife
  std::string safety_model_path;                     // empty: the installed force model (assets/safety/)
  std::string snapshot_key_file;                     // empty: a random key, snapshots stay with this process
  std::uint64_t memory_budget_mb = 0;                // all sessions together; 0: 3/4 of the machine's memory
  std::uint32_t max_handler_threads = 64;            // gRPC threads serving calls at once
  std::uint32_t step_cores = 0;                      // cores the Steps running at once share; 0: the machine's
  std::string step_threads = "shared";               // shared: cores / Steps running; model: each its food's
  ConnectionLimits connections;                      // TCP connections at once, all and per client address
  AccessOptions access;                              // TLS and bearer tokens; none by default
  // Off loopback the server needs TLS and authentication (tokens or client certificates) unless
  // this is set, and then says loudly that anyone who reaches the port controls every session.
  bool insecure = false;
};

}  // namespace culinarycut::server
