// The paper's safe-velocity definition: v_safe = max v s.t. R(v, m) <= F_max, found by bisection on
// the fitted force model (which never decreases with speed, see force_model.h).
#pragma once

#include "sim/safety/force_model.h"

namespace culinarycut::safety {

// v_safe is feasible (F_hat(v_safe) <= F_max) and within this of the largest feasible speed.
inline constexpr double kSafeSpeedToleranceMS = 1e-4;

struct SafeSpeed {
  double v_safe_m_s = 0.0;         // 0 when even a still knife is predicted past F_max
  double predicted_force_n = 0.0;  // F_hat(v_safe)
  bool out_of_range = false;       // the prediction at v_safe extrapolates (its factor applied)
};

// Searches [0, top of the model's speed range]: the top when F_hat(top) <= F_max, 0 when
// F_hat(0) > F_max. Below the speed range's low end the out-of-range factor applies, so F_hat is
// monotone on [0, low) and on [low, top] separately; each is bisected on its own.
SafeSpeed SafeCuttingSpeed(const ForceModel& model, const CutMaterial& material, double max_force_n,
                           double tolerance_m_s = kSafeSpeedToleranceMS);

}  // namespace culinarycut::safety
