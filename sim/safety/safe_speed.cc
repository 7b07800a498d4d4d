#include "sim/safety/safe_speed.h"

namespace culinarycut::safety {

SafeSpeed SafeCuttingSpeed(const ForceModel& model, const CutMaterial& material, double max_force_n,
                           double tolerance_m_s) {
  const InputRange& speeds = model.ranges[static_cast<int>(ForceInput::kSpeed)];
  const auto feasible = [&](double speed_m_s) {
    return PredictPeakForce(model, speed_m_s, material).force_n <= max_force_n;
  };
  const auto result = [&](double speed_m_s) {
    const ForcePrediction prediction = PredictPeakForce(model, speed_m_s, material);
    return SafeSpeed{speed_m_s, prediction.force_n, prediction.out_of_range};
  };
  if (feasible(speeds.high)) return result(speeds.high);
  double low = 0.0, high = speeds.low;  // the bracket: feasible at low, infeasible at high
  if (feasible(speeds.low)) {
    low = speeds.low;
    high = speeds.high;
  } else if (!feasible(0.0)) {
    return result(0.0);
  }
  while (high - low > tolerance_m_s) {
    const double middle = 0.5 * (low + high);
    (feasible(middle) ? low : high) = middle;
  }
  return result(low);
}

}  // namespace culinarycut::safety
