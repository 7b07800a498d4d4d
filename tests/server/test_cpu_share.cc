// The cores shared among the Steps running at once: every Step gets cores / running (at least one);
// the "model" policy sets no limit.
#include <catch2/catch.hpp>

#include <optional>

#include "server/cpu_share.h"

using culinarycut::server::CpuShare;

TEST_CASE("Steps running at once share the cores, at least one thread each", "[server][threads]") {
  CpuShare share(4, true);
  CHECK(share.ThreadsPerStep() == 4);  // nobody running: a Step about to start gets them all
  std::optional<CpuShare::Seat> first(&share);
  CHECK(first->Threads() == 4);
  {
    const CpuShare::Seat second(&share);
    CHECK(first->Threads() == 2);  // asked again before each physics step: the first Step shrinks too
    CHECK(second.Threads() == 2);
    const CpuShare::Seat third(&share), fourth(&share), fifth(&share);
    CHECK(fifth.Threads() == 1);  // more Steps than cores: one thread each, never zero
  }
  CHECK(first->Threads() == 4);  // the others ended
  first.reset();
  CHECK(CpuShare(0, true).cores() >= 1);  // 0: the machine's cores
}

TEST_CASE("the model policy leaves every Step its food's threads", "[server][threads]") {
  CpuShare share(2, false);
  const CpuShare::Seat a(&share), b(&share), c(&share);
  CHECK(a.Threads() == 0);  // 0: no limit
}
