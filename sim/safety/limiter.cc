#include "sim/safety/limiter.h"

#include <cmath>
#include <sstream>

#include "sim/safety/safe_speed.h"

namespace culinarycut::safety {

std::optional<Guard> ParseGuard(const std::string& name) {
  for (int i = 0; i < kGuardCount; ++i) {
    if (name == kGuardNames[i]) return static_cast<Guard>(i);
  }
  return std::nullopt;
}

IntoFoodLimit LimitIntoFood(const LimiterSettings& settings, const ForceModel& model, const LimiterInputs& inputs) {
  IntoFoodLimit limit;
  std::ostringstream reason;
  const double force_threshold_n = (1.0 - settings.margin) * settings.max_force_n;
  if (settings.enabled(Guard::kForce) && inputs.knife_force_n > force_threshold_n) {
    limit.holding[static_cast<int>(Guard::kForce)] = true;
    reason << "knife force " << inputs.knife_force_n << " N above " << force_threshold_n << " N";
  }
  const bool entering = !inputs.foods_near_edge.empty();
  if (settings.enabled(Guard::kEntryAngle) && entering && inputs.blade_tilt_deg > settings.max_entry_angle_deg) {
    limit.holding[static_cast<int>(Guard::kEntryAngle)] = true;
    if (reason.tellp() > 0) reason << "; ";
    reason << "blade tilted " << inputs.blade_tilt_deg << " deg from vertical (max " << settings.max_entry_angle_deg << ")";
  }
  limit.hold_reason = reason.str();
  if (settings.enabled(Guard::kSpeed)) {
    // The most restrictive food near the edge binds (several foods: the smallest v_safe).
    for (const CutMaterial& food : inputs.foods_near_edge) {
      const SafeSpeed safe = SafeCuttingSpeed(model, food, settings.max_force_n);
      if (std::isnan(limit.v_safe_m_s) || safe.v_safe_m_s < limit.v_safe_m_s) {
        limit.v_safe_m_s = safe.v_safe_m_s;
        limit.predicted_force_n = safe.predicted_force_n;
        limit.out_of_range = safe.out_of_range;
      }
    }
    if (entering) limit.max_speed_m_s = limit.v_safe_m_s * (1.0 - settings.margin);
  }
  return limit;
}

double LargestScaleWithin(const std::function<double(double)>& displacement_m, double cap_m, double tolerance) {
  if (displacement_m(1.0) <= cap_m) return 1.0;
  double low = 0.0, high = 1.0;  // fits at low, not at high
  while (high - low > tolerance) {
    const double middle = 0.5 * (low + high);
    (displacement_m(middle) <= cap_m ? low : high) = middle;
  }
  return low;
}

}  // namespace culinarycut::safety
