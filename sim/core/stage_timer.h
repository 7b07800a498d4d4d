// Wall-clock time per named stage of Step and Observe. Kept apart from the simulation State: timing
// is a measurement of the machine, never an input to physics, so it cannot break determinism.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace culinarycut {

// Robot control (action -> joint targets), the robot's physics substeps, the food's MPM substeps,
// piece detection, the task score, camera rendering, the safety limiter (only with it on), saving
// what a cancelled step puts back.
enum class Stage { kControl = 0, kPhysics, kMpm, kTopology, kTask, kRender, kSafety, kRollback, kCount };
inline constexpr int kStageCount = static_cast<int>(Stage::kCount);

// The names the wire and the docs use for each Stage, in enum order.
inline constexpr std::array<const char*, kStageCount> kStageNames = {"control", "physics", "mpm",    "topology",
                                                                    "task",    "render",  "safety", "rollback"};

// Wall time (ms) of each stage within one call.
struct StageTimes {
  std::array<double, kStageCount> wall_ms{};

  double& operator[](Stage stage) { return wall_ms[static_cast<int>(stage)]; }
  double operator[](Stage stage) const { return wall_ms[static_cast<int>(stage)]; }
};

// Running totals over many calls (a session's profile, MuJoCo's mjTimerStat).
struct StageTotals {
  std::array<double, kStageCount> wall_s{};
  std::array<std::uint64_t, kStageCount> calls{};

  // A stage counts as called in a call where it ran, i.e. took any time.
  void Add(const StageTimes& times) {
    for (int i = 0; i < kStageCount; ++i) {
      if (times.wall_ms[i] <= 0.0) continue;
      wall_s[i] += 1e-3 * times.wall_ms[i];
      calls[i] += 1;
    }
  }
};

inline double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The one timing helper: adds the wall time from construction to destruction to one stage.
class StageClock {
 public:
  StageClock(StageTimes* times, Stage stage) : slot_(&(*times)[stage]), start_(std::chrono::steady_clock::now()) {}
  ~StageClock() { *slot_ += MillisecondsSince(start_); }
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

 private:
  double* slot_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace culinarycut
