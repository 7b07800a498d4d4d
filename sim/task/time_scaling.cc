#include "sim/task/time_scaling.h"

#include <algorithm>

namespace culinarycut::task {
namespace {

// Integral of the smoothstep from 0 to x: x^3 - x^4 / 2 (equals 1/2 at x = 1).
double SmoothStepIntegral(double x) { return x * x * x - 0.5 * x * x * x * x; }

}  // namespace

TimeScaling QuinticScaling(double duration_s) {
  TimeScaling scaling;
  scaling.kind = TimeScaling::Kind::kQuintic;
  scaling.duration_s = duration_s;
  return scaling;
}

TimeScaling CruiseScaling(double distance, double speed, double ramp_s) {
  TimeScaling scaling;
  scaling.kind = TimeScaling::Kind::kCruise;
  scaling.cruise_rate_per_s = speed / distance;
  const double cruise_only_s = distance / speed;
  // Two half-ramps cover speed * ramp_s; a shorter path is all ramp.
  scaling.ramp_s = std::min(ramp_s, cruise_only_s);
  scaling.duration_s = cruise_only_s + scaling.ramp_s;
  return scaling;
}

Progress Evaluate(const TimeScaling& scaling, double t_s) {
  const double duration = scaling.duration_s;
  if (duration <= 0.0) return {t_s <= 0.0 ? 0.0 : 1.0, 0.0};
  const double t = std::clamp(t_s, 0.0, duration);
  if (scaling.kind == TimeScaling::Kind::kQuintic) {
    const double x = t / duration;
    const double x3 = x * x * x;
    const double one_minus = 1.0 - x;
    return {x3 * (10.0 - 15.0 * x + 6.0 * x * x),
            30.0 * x * x * one_minus * one_minus / duration};
  }
  const double rate = scaling.cruise_rate_per_s;
  const double ramp = scaling.ramp_s;
  if (ramp > 0.0 && t < ramp) {
    const double x = t / ramp;
    return {rate * ramp * SmoothStepIntegral(x), rate * SmoothStep(x)};
  }
  if (ramp > 0.0 && t > duration - ramp) {
    const double x = (duration - t) / ramp;
    return {1.0 - rate * ramp * SmoothStepIntegral(x), rate * SmoothStep(x)};
  }
  return {rate * (0.5 * ramp + t - ramp), rate};
}

double SmoothStep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

double SmoothStepSlope(double x) {
  if (x <= 0.0 || x >= 1.0) return 0.0;
  return 6.0 * x * (1.0 - x);
}

}  // namespace culinarycut::task
