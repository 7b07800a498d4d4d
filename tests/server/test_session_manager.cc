#include <catch2/catch.hpp>

#include <set>

#include "server/session_manager.h"
#include "support/robot_fixture.h"

using namespace culinarycut;
using namespace culinarycut::server;

TEST_CASE("the session manager caps sessions and finds them by id", "[sessions]") {
  SessionManager sessions(2, std::chrono::seconds(60));
  const auto model = testing::DefaultModel();
  const auto a = sessions.Create(model, "");
  const auto b = sessions.Create(model, "");
  REQUIRE(a);
  REQUIRE(b);
  CHECK(a->id != b->id);
  CHECK_FALSE(sessions.Create(model, ""));
  CHECK(sessions.Find(a->id, "") == a);
  CHECK(sessions.Close(a->id));
  CHECK_FALSE(sessions.Find(a->id, ""));
  CHECK(sessions.Create(model, ""));
}

TEST_CASE("another owner's calls neither find a session nor keep it alive", "[sessions]") {
  SessionManager sessions(4, std::chrono::seconds(10));
  const auto mine = sessions.Create(testing::DefaultModel(), "token:alice");
  REQUIRE(mine);
  const auto created = mine->last_used.load();
  CHECK_FALSE(sessions.Find(mine->id, "token:mallory"));
  CHECK(mine->last_used.load() == created);  // the stranger's call did not touch the idle timer
  CHECK(sessions.Find(mine->id, "token:alice") == mine);
}

TEST_CASE("one owner holds at most its quota of sessions; others still get theirs", "[sessions]") {
  SessionManager sessions(4, std::chrono::seconds(10), 0, 2);
  const auto model = testing::DefaultModel();
  CHECK(sessions.max_sessions_per_owner() == 2);
  REQUIRE(sessions.Create(model, "token:alice"));
  const auto second = sessions.Create(model, "token:alice");
  REQUIRE(second);
  std::string refusal;
  CHECK_FALSE(sessions.Create(model, "token:alice", &refusal));
  CHECK_THAT(refusal, Catch::Contains("--max-sessions-per-owner 2"));
  CHECK(sessions.Create(model, "token:bob"));
  CHECK(sessions.Close(second->id));
  CHECK(sessions.Create(model, "token:alice"));
  CHECK(SessionManager(4, std::chrono::seconds(10)).max_sessions_per_owner() == 4);  // 0: no quota below the cap
}

TEST_CASE("idle sessions are reaped, used ones are kept", "[sessions]") {
  SessionManager sessions(4, std::chrono::seconds(10));
  const auto model = testing::DefaultModel();
  const auto idle = sessions.Create(model, "");
  const auto busy = sessions.Create(model, "");
  const auto later = std::chrono::steady_clock::now() + std::chrono::seconds(11);
  busy->last_used = later.time_since_epoch().count();  // as if called just before `later`
  const std::vector<std::string> reaped = sessions.ReapIdle(later);
  REQUIRE(reaped.size() == 1);
  CHECK(reaped[0] == idle->id);
  CHECK(sessions.Find(busy->id, ""));
}

TEST_CASE("a session inside a call is never reaped, however long the call", "[sessions]") {
  SessionManager sessions(4, std::chrono::seconds(10));
  const auto model = testing::DefaultModel();
  const auto stepping = sessions.Create(model, "");
  const auto later = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  {
    SessionLock call(*stepping);  // a Step in flight for a minute
    CHECK(sessions.ReapIdle(later).empty());
  }
  // The call just ended: the session counts as used now, so it is not reaped at the call's end.
  CHECK(sessions.ReapIdle(std::chrono::steady_clock::now() + std::chrono::seconds(5)).empty());
  CHECK(sessions.ReapIdle(later + std::chrono::seconds(60)).size() == 1);
}

TEST_CASE("session ids carry 128 random bits", "[sessions]") {
  SessionManager sessions(64, std::chrono::seconds(10));
  const auto model = testing::DefaultModel();
  std::set<std::string> ids;
  for (int i = 0; i < 64; ++i) {
    const auto session = sessions.Create(model, "");
    REQUIRE(session);
    CHECK(session->id.size() == 2 + 32);
    CHECK(session->id.rfind("s-", 0) == 0);
    CHECK(session->id.find_first_not_of("0123456789abcdef", 2) == std::string::npos);
    ids.insert(session->id);
  }
  CHECK(ids.size() == 64);
}
