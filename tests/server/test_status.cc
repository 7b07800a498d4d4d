// Status messages are safe to print: control bytes escaped, long echoes cut with a count.
#include <catch2/catch.hpp>

#include "server/status.h"

using culinarycut::server::SafeMessage;

TEST_CASE("status messages escape control bytes and cut long echoes", "[server][status]") {
  CHECK(SafeMessage("plain text: 1.5 m") == "plain text: 1.5 m");
  CHECK(SafeMessage(std::string("dur\0ian", 7)) == "dur\\x00ian");
  CHECK(SafeMessage("tab\there") == "tab\\x09here");
  const std::string echoed = "unknown food '" + std::string(1'600'000, 'x') + "'";
  const std::string safe = SafeMessage(echoed);
  CHECK(safe.size() < 1100);
  CHECK_THAT(safe, Catch::EndsWith("more characters)"));
  CHECK_THAT(safe, Catch::StartsWith("unknown food 'xxx"));
}
