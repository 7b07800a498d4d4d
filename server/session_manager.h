// Owns the live sessions. Each session has its own Model, State and mutex, so sessions step in
// parallel on gRPC's threads while calls into one session are serialised. Sessions idle longer
// than the timeout (a client that vanished) are reclaimed by a background reaper, never while a
// call is in them. Ids are 128 random bits from the operating system's cryptographic source.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
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
  // Its telemetry frames' ZeroMQ topic, "telemetry/<128 random bits>": unrelated to the id, so a subscriber
  // who reads every topic learns no handle to drive or close a session with.
  std::string telemetry_topic;
  std::string owner;  // the principal that created it (CallerPrincipal); others cannot find it
  std::shared_ptr<const Model> model;
  State state;
  // Set by Tasks.StartOracle; cleared by Reset and by a StartOracle that fails. RestoreSnapshot
  // keeps it, so a restored episode replays the same oracle actions.
  std::optional<ScriptedOracle> oracle;
  std::mutex mutex;  // held for the whole of any call into this session (SessionLock)
  // When a call last entered or left the session (steady clock, ns); atomic: the reaper reads it.
  std::atomic<std::chrono::steady_clock::rep> last_used{0};
  // Why the last Step failed half-way (an engine exception); empty while the state is consistent.
  // Reset and RestoreSnapshot clear it; Step, Observe and SaveSnapshot refuse until then.
  std::string broken_reason;
  StageTotals timers;  // wall time per stage over the session's life (GetSessionStats)

  bool broken() const { return !broken_reason.empty(); }
  void Touch() { last_used = std::chrono::steady_clock::now().time_since_epoch().count(); }
};

// Gives the memory of closed sessions back to the operating system (glibc keeps freed heap pages,
// so without it the server's RSS rose in steps over a soak; docs/benchmarks/soak.md).
void ReturnFreedMemory();

// Holds a session for the whole of one call and marks it used when the call leaves, so a call that
// outlasts the idle timeout does not leave its session to be reaped the moment it returns.
class SessionLock {
 public:
  explicit SessionLock(Session& session) : session_(session), lock_(session.mutex) {}
  ~SessionLock() { session_.Touch(); }
  SessionLock(const SessionLock&) = delete;
  SessionLock& operator=(const SessionLock&) = delete;

 private:
  Session& session_;
  std::lock_guard<std::mutex> lock_;
};

class SessionManager {
 public:
  // `memory_budget_bytes` bounds the sum of the live sessions' estimated memory (0: no bound);
  // `max_sessions_per_owner` the sessions one owner (token, certificate) may hold (0: max_sessions).
  SessionManager(std::uint32_t max_sessions, std::chrono::duration<double> idle_timeout,
                 std::uint64_t memory_budget_bytes = 0, std::uint32_t max_sessions_per_owner = 0);
  ~SessionManager();
  SessionManager(const SessionManager&) = delete;
  SessionManager& operator=(const SessionManager&) = delete;

  // Null, with the reason in `refusal` (naming the limit and what to lower), when the server
  // already holds max_sessions, the owner its quota, or the model's estimated memory would pass the budget.
  std::shared_ptr<Session> Create(std::shared_ptr<const Model> model, const std::string& owner,
                                  std::string* refusal = nullptr);
  // Null when no session `id` belongs to `owner`; marks it as used now only when it does (another
  // owner's calls must not keep it alive).
  std::shared_ptr<Session> Find(const std::string& id, const std::string& owner);
  bool Close(const std::string& id);
  // Closes sessions idle for longer than the timeout and not inside a call; returns their ids.
  std::vector<std::string> ReapIdle(std::chrono::steady_clock::time_point now);

  std::uint32_t size() const;
  // The server is stopping: Steps in flight give up at their next check and roll back, at once rather
  // than at the shutdown's grace deadline.
  void BeginStopping() { stopping_calls_ = true; }
  bool stopping() const { return stopping_calls_; }
  std::uint32_t max_sessions() const { return max_sessions_; }
  std::uint32_t max_sessions_per_owner() const { return max_sessions_per_owner_; }
  double idle_timeout_s() const { return idle_timeout_.count(); }
  std::uint64_t memory_budget_bytes() const { return memory_budget_bytes_; }
  std::uint64_t memory_reserved_bytes() const;

 private:
  void ReaperLoop();

  const std::uint32_t max_sessions_;
  const std::chrono::duration<double> idle_timeout_;
  const std::uint64_t memory_budget_bytes_;
  const std::uint32_t max_sessions_per_owner_;
  std::atomic<bool> stopping_calls_{false};
  std::uint64_t memory_reserved_bytes_ = 0;  // sum of the live sessions' Model::estimated_memory_bytes
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::condition_variable stop_signal_;
  bool stopping_ = false;
  std::thread reaper_;
};

}  // namespace culinarycut::server
