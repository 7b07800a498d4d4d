#include "server/session_manager.h"

#include <malloc.h>

#include <sys/random.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace culinarycut::server {
namespace {

// "s-" and 32 hex digits from getrandom(2): unguessable, so one client cannot find another's session.
// `prefix` and 128 random bits in hex.
std::string RandomHandle(const char* prefix) {
  unsigned char bytes[16];
  std::size_t filled = 0;
  while (filled < sizeof(bytes)) {
    const ssize_t got = getrandom(bytes + filled, sizeof(bytes) - filled, 0);
    if (got < 0) throw std::runtime_error("getrandom failed: no cryptographic randomness for session ids");
    filled += static_cast<std::size_t>(got);
  }
  char hex[1 + 2 * sizeof(bytes)] = {};
  for (std::size_t i = 0; i < sizeof(bytes); ++i) std::snprintf(hex + 2 * i, 3, "%02x", bytes[i]);
  return prefix + std::string(hex);
}

}  // namespace

SessionManager::SessionManager(std::uint32_t max_sessions, std::chrono::duration<double> idle_timeout,
                               std::uint64_t memory_budget_bytes, std::uint32_t max_sessions_per_owner)
    : max_sessions_(max_sessions),
      idle_timeout_(idle_timeout),
      memory_budget_bytes_(memory_budget_bytes),
      max_sessions_per_owner_(max_sessions_per_owner == 0 ? max_sessions : max_sessions_per_owner),
      reaper_([this] { ReaperLoop(); }) {}

SessionManager::~SessionManager() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  stop_signal_.notify_all();
  reaper_.join();
}

std::shared_ptr<Session> SessionManager::Create(std::shared_ptr<const Model> model, const std::string& owner,
                                               std::string* refusal) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (sessions_.size() >= max_sessions_) {
    if (refusal) {
      *refusal = "the server already runs its maximum of " + std::to_string(max_sessions_) +
                 " sessions; close one (CloseSession) or start the server with a larger --max-sessions";
    }
    return nullptr;
  }
  std::uint32_t owned = 0;
  for (const auto& [id, live] : sessions_) owned += live->owner == owner;
  if (owned >= max_sessions_per_owner_) {
    if (refusal) {
      *refusal = "this client already holds " + std::to_string(owned) + " sessions, its quota "
                 "(--max-sessions-per-owner " + std::to_string(max_sessions_per_owner_) +
                 "); close one (CloseSession) first";
    }
    return nullptr;
  }
  const std::uint64_t needed = model->estimated_memory_bytes;
  if (memory_budget_bytes_ > 0 && memory_reserved_bytes_ + needed > memory_budget_bytes_) {
    if (refusal) {
      *refusal = "this scene needs about " + std::to_string(needed >> 20) + " MB and the live sessions hold " +
                 std::to_string(memory_reserved_bytes_ >> 20) + " MB of the server's " +
                 std::to_string(memory_budget_bytes_ >> 20) +
                 " MB memory budget (--memory-budget-mb); lower scene.quality, the food's scale or the cameras' "
                 "size, or close sessions";
    }
    return nullptr;
  }
  memory_reserved_bytes_ += needed;
  auto session = std::make_shared<Session>();
  do {
    session->id = RandomHandle("s-");
  } while (sessions_.count(session->id) > 0);
  session->telemetry_topic = RandomHandle("telemetry/");
  session->model = std::move(model);
  session->owner = owner;
  session->Touch();
  sessions_[session->id] = session;
  return session;
}

std::shared_ptr<Session> SessionManager::Find(const std::string& id, const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(id);
  if (it == sessions_.end() || it->second->owner != owner) return nullptr;
  it->second->Touch();
  return it->second;
}

bool SessionManager::Close(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(id);
  if (it == sessions_.end()) return false;
  memory_reserved_bytes_ -= it->second->model->estimated_memory_bytes;
  sessions_.erase(it);
  return true;
}

std::uint64_t SessionManager::memory_reserved_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return memory_reserved_bytes_;
}

void ReturnFreedMemory() { malloc_trim(0); }

std::vector<std::string> SessionManager::ReapIdle(std::chrono::steady_clock::time_point now) {
  std::vector<std::string> reaped;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    Session& session = *it->second;
    const std::chrono::steady_clock::time_point last_used{std::chrono::steady_clock::duration(session.last_used.load())};
    // A session inside a call (its mutex held) is busy, however long the call takes.
    std::unique_lock<std::mutex> busy_check(session.mutex, std::try_to_lock);
    if (now - last_used > idle_timeout_ && busy_check.owns_lock()) {
      reaped.push_back(it->first);
      busy_check.unlock();
      memory_reserved_bytes_ -= it->second->model->estimated_memory_bytes;
      it = sessions_.erase(it);
    } else {
      ++it;
    }
  }
  return reaped;
}

std::uint32_t SessionManager::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<std::uint32_t>(sessions_.size());
}

void SessionManager::ReaperLoop() {
  // Check often enough that a session outlives its timeout by at most a quarter of it (and 1 s),
  // but no more than every 10 ms, so a tiny timeout does not spin a core.
  const auto period = std::max(std::chrono::milliseconds(10),
                               std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::min<std::chrono::duration<double>>(idle_timeout_ / 4, std::chrono::seconds(1))));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_signal_.wait_for(lock, period, [this] { return stopping_; })) {
    lock.unlock();
    const std::vector<std::string> reaped = ReapIdle(std::chrono::steady_clock::now());
    for (const std::string& id : reaped) {
      spdlog::info("session {} closed after {:.0f} s idle (client gone?)", id, idle_timeout_.count());
    }
    if (!reaped.empty()) ReturnFreedMemory();
    lock.lock();
  }
}

}  // namespace culinarycut::server
