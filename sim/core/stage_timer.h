// Wall-clock time spent in each named stage of Step, accumulated in the State (MuJoCo's mjTimerStat).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace culinarycut {

// Robot control, the robot's physics substeps, the food's MPM substeps, piece detection, camera rendering.
enum class Stage { kControl = 0, kPhysics, kMpm, kTopology, kRender, kCount };

struct StageTimers {
  std::array<double, static_cast<int>(Stage::kCount)> total_seconds{};
  std::array<std::uint64_t, static_cast<int>(Stage::kCount)> calls{};
};

inline double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Adds the lifetime of this object to one stage of a StageTimers, and reports it in `elapsed_ms`.
class ScopedStageTimer {
 public:
  ScopedStageTimer(StageTimers* timers, Stage stage, double* elapsed_ms)
      : timers_(timers), stage_(static_cast<int>(stage)), elapsed_ms_(elapsed_ms),
        start_(std::chrono::steady_clock::now()) {}
  ~ScopedStageTimer() {
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
    timers_->total_seconds[stage_] += elapsed.count();
    timers_->calls[stage_] += 1;
    *elapsed_ms_ = 1e3 * elapsed.count();
  }
  ScopedStageTimer(const ScopedStageTimer&) = delete;
  ScopedStageTimer& operator=(const ScopedStageTimer&) = delete;

 private:
  StageTimers* timers_;
  int stage_;
  double* elapsed_ms_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace culinarycut
