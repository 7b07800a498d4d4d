#include "sim/world/quality_preset.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/mpm/solver_config.h"
#include "sim/world/measured_accuracy.h"
#include "sim/world/model.h"

namespace culinarycut {
namespace {

struct NamedPreset {
  const char* name;
  MpmResolution resolution;
};

// standard was dx 4 mm, 8 ppc, CFL 0.2 until the accuracy study found CFL 0.4, then 6 ppc at CFL 0.5, then
// 6 ppc at CFL 0.8, as accurate on the study's cuts in less time (docs/accuracy.md); fine keeps CFL 0.2 as
// the study's reference does. draft was CFL 0.3 until the same study found CFL 0.6 as accurate (2026-11-28).
const NamedPreset kPresets[] = {
    {"draft", {0.008, 4, 0.6}},
    {"standard", {0.004, 6, 0.8}},
    {"fine", {0.002, 8, 0.2}},
};

}  // namespace

std::vector<std::string> QualityPresetNames() {
  std::vector<std::string> names;
  for (const NamedPreset& preset : kPresets) names.push_back(preset.name);
  return names;
}

std::string QualityNameOf(const MpmResolution& resolution) {
  for (const NamedPreset& preset : kPresets) {
    const MpmResolution& named = preset.resolution;
    if (named.dx_m == resolution.dx_m && named.particles_per_cell == resolution.particles_per_cell &&
        named.cfl == resolution.cfl) {
      return preset.name;
    }
  }
  return kAccuracyTargetQuality;
}

MpmResolution ResolveMpmResolution(const std::string& quality, const std::optional<AccuracyTargetConfig>& target,
                                   const MpmResolutionConfig& overrides) {
  const NamedPreset* found = nullptr;
  for (const NamedPreset& preset : kPresets) {
    if (quality == preset.name) found = &preset;
  }
  if (!found && !(quality == kAccuracyTargetQuality && target)) {
    throw SceneError("scene.quality must be \"draft\", \"standard\" or \"fine\", got \"" + quality + "\"");
  }
  MpmResolution resolution = target ? CheapestSettingMeeting(*target) : found->resolution;
  std::ostringstream error;
  if (overrides.dx_m) {
    if (!(*overrides.dx_m >= 0.001 && *overrides.dx_m <= 0.02)) {
      error << "scene.mpm.dx must be in [0.001, 0.02] m, got " << *overrides.dx_m;
      throw SceneError(error.str());
    }
    resolution.dx_m = *overrides.dx_m;
  }
  if (overrides.particles_per_cell) {
    if (*overrides.particles_per_cell < 1 || *overrides.particles_per_cell > 64) {
      error << "scene.mpm.particles_per_cell must be in [1, 64], got " << *overrides.particles_per_cell;
      throw SceneError(error.str());
    }
    resolution.particles_per_cell = *overrides.particles_per_cell;
  }
  if (overrides.cfl) {
    // Explicit MPM's elastic waves cross at most about a cell per substep: c dt = dx is its stability edge.
    if (!(*overrides.cfl > 0.0 && *overrides.cfl <= 1.0)) {
      error << "scene.mpm.cfl must be in (0, 1], got " << *overrides.cfl;
      throw SceneError(error.str());
    }
    resolution.cfl = *overrides.cfl;
  }
  if (overrides.mass_scaling) {
    if (!(*overrides.mass_scaling >= 1.0 && *overrides.mass_scaling <= mpm::kMaxMassScaling)) {
      error << "scene.mpm.mass_scaling must be in [1, " << mpm::kMaxMassScaling << "], got " << *overrides.mass_scaling;
      throw SceneError(error.str());
    }
    resolution.mass_scaling = *overrides.mass_scaling;
  }
  if (overrides.activity_radius_m) {
    const double radius_m = *overrides.activity_radius_m;
    // The solver's own rule (solver_config.h), said here in the scene's terms.
    if (!(radius_m == 0.0 || (radius_m >= mpm::kMinActivityRadiusCells * resolution.dx_m - 1e-12 && radius_m <= 1.0))) {
      error << "scene.mpm.activity_radius must be 0 (off) or in [5 dx, 1] m = ["
            << mpm::kMinActivityRadiusCells * resolution.dx_m
            << ", 1] m, got " << radius_m;
      throw SceneError(error.str());
    }
    resolution.activity_radius_m = radius_m;
  }
  return resolution;
}

double DxForSmallestFood(double resolved_dx_m, double smallest_food_m3) {
  const double spanning_dx_m = std::cbrt(smallest_food_m3 / kMinCellsPerFood);
  return std::clamp(spanning_dx_m, 0.5 * resolved_dx_m, resolved_dx_m);
}

}  // namespace culinarycut
