// The robot's physics loop allocates nothing (MuJoCo's rule for mj_step): a step with twice the
// physics substeps makes exactly as many heap allocations as one with half as many.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>

#include "sim/world/step.h"
#include "support/robot_fixture.h"

namespace {
std::atomic<long> allocation_count{0};
}  // namespace

// Counts every heap allocation of the test binary: operator new and Eigen both end in malloc, which
// this executable interposes (glibc resolves malloc to the program's own definition first).
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* malloc(std::size_t size) {
  allocation_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  allocation_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) {
  allocation_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(pointer, size);
}
}

using namespace culinarycut;

namespace {

// Heap allocations of one Step with `physics_hz` physics substeps per second at 20 Hz control,
// after a few warm-up steps (Bullet sizes its caches on the first ones).
long AllocationsPerStep(double physics_hz, ControlMode mode, int action_size) {
  SceneConfig config;
  config.robot.physics_frequency_hz = physics_hz;
  const auto model = testing::DefaultModel(config);
  State state;
  ResetState(*model, &state, 0, {});
  const Action action{mode, Eigen::VectorXd::Zero(action_size)};
  for (int i = 0; i < 5; ++i) Step(*model, &state, action);
  const long before = allocation_count.load();
  Step(*model, &state, action);
  return allocation_count.load() - before;
}

}  // namespace

TEST_CASE("the robot's physics loop allocates nothing per substep", "[step][allocations]") {
  for (const auto& [mode, size] : {std::pair{ControlMode::kJointDeltaPosition, 7}, std::pair{ControlMode::kEndEffectorDeltaPose, 6}}) {
    const long at_500_hz = AllocationsPerStep(500.0, mode, size);    // 25 substeps
    const long at_1000_hz = AllocationsPerStep(1000.0, mode, size);  // 50 substeps
    INFO("mode " << ControlModeName(mode) << ": " << at_500_hz << " allocations at 25 substeps, " << at_1000_hz
                 << " at 50");
    CHECK(at_1000_hz == at_500_hz);
  }
}
