// The paper's quadratic speed resistance of the knife in the food, in one place and one set of units:
// u <- u / (1 + k2 c-hat u dt), with u the knife's speed in m/s (the world and cc-cut both use it).
#pragma once

#include "sim/mpm/solver.h"

namespace culinarycut::mpm {

// k2 c-hat dt of one substep (s/m), from the solver's factor 1 / (1 + k2 c-hat dt) at u = 1 m/s.
inline double SubstepResistance(const SubstepDiagnostics& substep) { return 1.0 / substep.knife_speed_factor - 1.0; }

// The fraction of its speed a knife moving at `speed_m_s` keeps over substeps whose resistances sum to
// `resistance_s_per_m` (sum of k2 c-hat dt): 1 / (1 + u sum).
inline double SpeedResistanceFactor(double speed_m_s, double resistance_s_per_m) {
  return 1.0 / (1.0 + speed_m_s * resistance_s_per_m);
}

}  // namespace culinarycut::mpm
