#include <catch2/catch.hpp>

#include "server/session_manager.h"
#include "support/robot_fixture.h"

using namespace culinarycut;
using namespace culinarycut::server;

TEST_CASE("the session manager caps sessions and finds them by id", "[sessions]") {
  SessionManager sessions(2, std::chrono::seconds(60));
  const auto model = testing::DefaultModel();
  const auto a = sessions.Create(model);
  const auto b = sessions.Create(model);
  REQUIRE(a);
  REQUIRE(b);
  CHECK(a->id != b->id);
  CHECK_FALSE(sessions.Create(model));
  CHECK(sessions.Find(a->id) == a);
  CHECK(sessions.Close(a->id));
  CHECK_FALSE(sessions.Find(a->id));
  CHECK(sessions.Create(model));
}

TEST_CASE("idle sessions are reaped, used ones are kept", "[sessions]") {
  SessionManager sessions(4, std::chrono::seconds(10));
  const auto model = testing::DefaultModel();
  const auto idle = sessions.Create(model);
  const auto busy = sessions.Create(model);
  const auto later = std::chrono::steady_clock::now() + std::chrono::seconds(11);
  busy->last_used = later;  // as if called just before `later`
  const std::vector<std::string> reaped = sessions.ReapIdle(later);
  REQUIRE(reaped.size() == 1);
  CHECK(reaped[0] == idle->id);
  CHECK(sessions.Find(busy->id));
}
