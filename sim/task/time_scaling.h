// Time scalings for the cut planner: how a segment's progress s runs from 0 to 1 over its
// duration, starting and ending at rest.
#pragma once

namespace culinarycut::task {

// Progress along a segment and its rate of change.
struct Progress {
  double s = 0.0;           // 0 at the segment's start, 1 at its end
  double rate_per_s = 0.0;  // ds/dt
};

// Peak ds/dt of the quintic scaling is this over the duration (at mid-time).
inline constexpr double kQuinticPeakRate = 1.875;

struct TimeScaling {
  // kQuintic: minimum-jerk rest-to-rest. kCruise: constant rate with smooth ramps at both ends.
  enum class Kind { kQuintic, kCruise };
  Kind kind = Kind::kQuintic;
  double duration_s = 0.0;
  double ramp_s = 0.0;             // kCruise: time to reach the cruise rate, and to stop again
  double cruise_rate_per_s = 0.0;  // kCruise: ds/dt between the ramps
};

// Minimum-jerk scaling over `duration_s` (> 0).
TimeScaling QuinticScaling(double duration_s);

// Covers `distance` (> 0) at a constant `speed` (> 0) between cubic ramps of `ramp_s`; the ramps
// shrink when the distance is shorter than speed * ramp_s, so the speed never exceeds `speed`.
TimeScaling CruiseScaling(double distance, double speed, double ramp_s);

// Progress at `t_s`, clamped to [0, duration].
Progress Evaluate(const TimeScaling& scaling, double t_s);

// Cubic smoothstep 3x^2 - 2x^3 (x clamped to [0, 1]) and its derivative; max slope is 1.5.
double SmoothStep(double x);
double SmoothStepSlope(double x);
inline constexpr double kSmoothStepMaxSlope = 1.5;

}  // namespace culinarycut::task
