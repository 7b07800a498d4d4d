#include "server/session_manager.h"

#include <algorithm>
#include <cstdio>
#include <random>

#include <spdlog/spdlog.h>

namespace culinarycut::server {

SessionManager::SessionManager(std::uint32_t max_sessions, std::chrono::duration<double> idle_timeout)
    : max_sessions_(max_sessions),
      idle_timeout_(idle_timeout),
      // Ids only need to be unique and hard to guess; simulation randomness never comes from here.
      id_generator_(std::random_device{}()),
      reaper_([this] { ReaperLoop(); }) {}

SessionManager::~SessionManager() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  stop_signal_.notify_all();
  reaper_.join();
}

std::shared_ptr<Session> SessionManager::Create(std::shared_ptr<const Model> model) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (sessions_.size() >= max_sessions_) return nullptr;
  auto session = std::make_shared<Session>();
  std::uniform_int_distribution<unsigned long long> digits(0, 0xffffffffffffULL);
  char id[32];
  do {
    std::snprintf(id, sizeof(id), "s-%012llx", digits(id_generator_));
  } while (sessions_.count(id) > 0);
  session->id = id;
  session->model = std::move(model);
  session->last_used = std::chrono::steady_clock::now();
  sessions_[session->id] = session;
  return session;
}

std::shared_ptr<Session> SessionManager::Find(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(id);
  if (it == sessions_.end()) return nullptr;
  it->second->last_used = std::chrono::steady_clock::now();
  return it->second;
}

bool SessionManager::Close(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  return sessions_.erase(id) > 0;
}

std::vector<std::string> SessionManager::ReapIdle(std::chrono::steady_clock::time_point now) {
  std::vector<std::string> reaped;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (now - it->second->last_used > idle_timeout_) {
      reaped.push_back(it->first);
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
    for (const std::string& id : ReapIdle(std::chrono::steady_clock::now())) {
      spdlog::info("session {} closed after {:.0f} s idle (client gone?)", id, idle_timeout_.count());
    }
    lock.lock();
  }
}

}  // namespace culinarycut::server
