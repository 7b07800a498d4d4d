// Owns the live sessions. Each session has its own Model, State and mutex, so sessions step in
// parallel on gRPC's threads while calls into one session are serialised. Sessions idle longer
// than the timeout (a client that vanished) are reclaimed by a background reaper.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "sim/core/stage_timer.h"
#include "sim/policy/scripted_oracle.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut::server {

struct Session {
  std::string id;
  std::shared_ptr<const Model> model;
  State state;
  // Set by Tasks.StartOracle; cleared by Reset and by a StartOracle that fails. RestoreSnapshot
  // keeps it, so a restored episode replays the same oracle actions.
  std::optional<ScriptedOracle> oracle;
  std::mutex mutex;  // held for the whole of any call into this session
  std::chrono::steady_clock::time_point last_used;
  // Why the last Step failed half-way (an engine exception); empty while the state is consistent.
  // Reset and RestoreSnapshot clear it; Step, Observe and SaveSnapshot refuse until then.
  std::string broken_reason;
  StageTotals timers;  // wall time per stage over the session's life (GetSessionStats)

  bool broken() const { return !broken_reason.empty(); }
};

class SessionManager {
 public:
  SessionManager(std::uint32_t max_sessions, std::chrono::duration<double> idle_timeout);
  ~SessionManager();
  SessionManager(const SessionManager&) = delete;
  SessionManager& operator=(const SessionManager&) = delete;

  // Null when the server already holds max_sessions.
  std::shared_ptr<Session> Create(std::shared_ptr<const Model> model);
  // Null when no such session exists; marks the session as used now.
  std::shared_ptr<Session> Find(const std::string& id);
  bool Close(const std::string& id);
  // Closes sessions idle for longer than the timeout; returns their ids.
  std::vector<std::string> ReapIdle(std::chrono::steady_clock::time_point now);

  std::uint32_t size() const;
  std::uint32_t max_sessions() const { return max_sessions_; }
  double idle_timeout_s() const { return idle_timeout_.count(); }

 private:
  void ReaperLoop();

  const std::uint32_t max_sessions_;
  const std::chrono::duration<double> idle_timeout_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::mt19937_64 id_generator_;
  std::condition_variable stop_signal_;
  bool stopping_ = false;
  std::thread reaper_;
};

}  // namespace culinarycut::server
