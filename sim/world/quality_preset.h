// MPM accuracy presets: grid spacing, particles per cell and CFL factor. Explicit values in the
// scene override the preset's, one by one.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/world/scene_config.h"

namespace culinarycut {

// No defaults for the grid, the particles and the step: the presets below (quality_preset.cc) are their
// one source, and an unset (zero) resolution is refused by the solver rather than run at a stale setting.
struct MpmResolution {
  double dx_m = 0.0;            // grid spacing
  int particles_per_cell = 0;   // per dx^3 cell
  double cfl = 0.0;             // dt = cfl dx / wave speed
  double mass_scaling = 1.0;    // inertia multiplier (sim/mpm/solver_config.h); 1 = real mass
  double activity_radius_m = 0.0;  // food this far from the knife may freeze (solver_config.h); 0 = off
};

// draft: fast enough for tests and quick looks; standard: the paper's resolution; fine: studies.
// draft and standard are the cheapest settings on the accuracy study's front at their accuracy
// (docs/accuracy.md); measured_accuracy.h gives each one's expected error and cost.
std::vector<std::string> QualityPresetNames();

// The `quality` a resolved scene names when an accuracy target chose a setting that is no preset.
inline constexpr const char* kAccuracyTargetQuality = "accuracy_target";

// The name of the preset whose grid, particles per cell and CFL `resolution` has, or kAccuracyTargetQuality.
std::string QualityNameOf(const MpmResolution& resolution);

// The preset named `quality`, or with `target` the cheapest measured setting that meets it
// (measured_accuracy.h), with the explicit values of `overrides` applied. `quality` may be
// kAccuracyTargetQuality only with a target. Throws SceneError naming the field for an unknown preset,
// an unreachable target or an out-of-range value.
MpmResolution ResolveMpmResolution(const std::string& quality, const std::optional<AccuracyTargetConfig>& target,
                                   const MpmResolutionConfig& overrides);

// Cells of its own volume the smallest food spans at least, so that its halves are pieces of many
// particles: at draft's 8 mm a 25 mm strawberry is 13 cells (77 particles) and a bias cut leaves it
// in crumbs; at 30 cells it parts.
inline constexpr double kMinCellsPerFood = 64.0;

// The grid spacing (m) for a scene whose smallest food has `smallest_food_m3`: the resolved dx, or
// finer where that food would span fewer than kMinCellsPerFood cells, never below half the resolved
// dx (a tiny food beside a large one must not multiply the large one's particles without bound).
double DxForSmallestFood(double resolved_dx_m, double smallest_food_m3);

}  // namespace culinarycut
