// The paper's manipulation safety module, as pure logic: from what the knife is about to enter and
// what it measures, how far the knife may move into the food this control step. Three guards:
//   speed:       the knife's speed along its cutting direction <= v_safe (1 - margin), v_safe from the
//                force model for the most restrictive food near the edge (the paper's safe velocity);
//   force:       the measured knife force above (1 - margin) F_max: no further motion into the food;
//   entry_angle: the blade tilted from vertical by more than the maximum while entering: no motion
//                into the food until the tilt is corrected.
// sim/world's safety stage gathers the geometry and turns the limit into a scaled joint target.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/safety/force_model.h"

namespace culinarycut::safety {

enum class Guard { kSpeed = 0, kForce, kEntryAngle };
inline constexpr int kGuardCount = 3;
inline constexpr std::array<const char*, kGuardCount> kGuardNames = {"speed", "force", "entry_angle"};
std::optional<Guard> ParseGuard(const std::string& name);

struct LimiterSettings {
  double max_force_n = 100.0;  // F_max: the Panda's safe contact force
  double margin = 0.1;         // in [0, 0.9]: caps at (1 - margin) of v_safe and of F_max
  std::array<bool, kGuardCount> guards = {true, true, true};
  double max_entry_angle_deg = 15.0;  // blade tilt from vertical allowed while entering the food
  // The edge this close to a food's box (m), now or along the commanded motion, counts as entering it.
  double approach_distance_m = 0.02;
  bool enabled(Guard guard) const { return guards[static_cast<int>(guard)]; }
};

// What a compiled scene's limiter needs: its settings and the shared, read-only force model.
struct LimiterModel {
  LimiterSettings settings;
  std::shared_ptr<const ForceModel> force_model;
};

// What the knife faces this control step (gathered by the world).
struct LimiterInputs {
  std::vector<CutMaterial> foods_near_edge;  // each food within approach distance of the edge
  double blade_tilt_deg = 0.0;               // cutting direction from straight down
  double knife_force_n = 0.0;                // measured: the food's force on the knife, magnitude
};

// How far the knife may go into the food this step.
struct IntoFoodLimit {
  double max_speed_m_s = std::numeric_limits<double>::infinity();  // along the cutting direction
  std::array<bool, kGuardCount> holding{};  // force / entry angle: no motion into the food at all
  std::string hold_reason;                  // why, when some guard holds
  // The speed guard's assessment (NaN when no food is near the edge, or the guard is off).
  double v_safe_m_s = std::numeric_limits<double>::quiet_NaN();
  double predicted_force_n = std::numeric_limits<double>::quiet_NaN();  // F_hat(v_safe) of the binding food
  bool out_of_range = false;
  bool holds() const { return holding[static_cast<int>(Guard::kForce)] || holding[static_cast<int>(Guard::kEntryAngle)]; }
};

IntoFoodLimit LimitIntoFood(const LimiterSettings& settings, const ForceModel& model, const LimiterInputs& inputs);

// The largest s in [0, 1] with displacement_m(s) <= cap_m, by bisection to `tolerance` (displacement(0)
// is 0 <= cap). Used to shorten a joint-space step q + s dq until the knife's motion into the food fits.
double LargestScaleWithin(const std::function<double(double)>& displacement_m, double cap_m, double tolerance = 1e-3);

// What the limiter did in one control step.
struct LimiterReport {
  bool acted = false;                                   // the joint target was shortened
  std::array<std::uint32_t, kGuardCount> guard_counts{};  // 1 for each guard that bound this step
  std::string reason;                                   // empty when it did not act
  double v_safe_m_s = std::numeric_limits<double>::quiet_NaN();
  double predicted_force_n = std::numeric_limits<double>::quiet_NaN();
  bool out_of_range = false;
  double commanded_speed_m_s = 0.0;  // into the food, before the limit (peak of the PD servo)
  double target_scale = 1.0;         // the joint step's scale, in [0, 1]
};

// The episode's safety record (part of the State): interventions and peaks, and the last step's
// assessment for telemetry.
struct EpisodeSafety {
  std::array<std::uint64_t, kGuardCount> interventions{};
  double peak_knife_force_n = 0.0;   // |food force on the knife| over every physics step
  double peak_cutting_speed_m_s = 0.0;  // the TCP along its cutting direction, while in contact
  double v_safe_m_s = std::numeric_limits<double>::quiet_NaN();
  double predicted_force_n = std::numeric_limits<double>::quiet_NaN();
  bool out_of_range = false;
};

}  // namespace culinarycut::safety
