#include "sim/world/measured_accuracy.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/world/model.h"

namespace culinarycut {
namespace {

bool Same(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }

bool SameSetting(const MpmResolution& a, const MpmResolution& b) {
  return Same(a.dx_m, b.dx_m) && a.particles_per_cell == b.particles_per_cell && Same(a.cfl, b.cfl) &&
         Same(a.mass_scaling, b.mass_scaling) && Same(a.activity_radius_m, b.activity_radius_m);
}

// Levers whose price depends on the cut (mass scaling: slow cuts only; activity: the food's length
// and the knife's speed) are left to the user: no target resolves to them.
bool LeftToUser(const MpmResolution& resolution) {
  return resolution.mass_scaling != 1.0 || resolution.activity_radius_m != 0.0;
}

struct Bound {
  const char* field;
  std::optional<double> limit;
  double MeasuredAccuracy::*error;
};

}  // namespace

std::optional<MeasuredAccuracy> FindMeasuredAccuracy(const MpmResolution& resolution) {
  for (const MeasuredAccuracy& measured : MeasuredAccuracies()) {
    if (SameSetting(measured.resolution, resolution)) return measured;
  }
  return std::nullopt;
}

MpmResolution CheapestSettingMeeting(const AccuracyTargetConfig& target) {
  const Bound bounds[] = {
      {"force_error", target.force_error, &MeasuredAccuracy::peak_force_error},
      {"force_curve_error", target.force_curve_error, &MeasuredAccuracy::force_curve_error},
      {"cut_position_error_mm", target.cut_position_error_mm, &MeasuredAccuracy::cut_position_error_mm},
  };
  bool any = false;
  for (const Bound& bound : bounds) {
    if (!bound.limit) continue;
    any = true;
    if (!(std::isfinite(*bound.limit) && *bound.limit > 0.0)) {
      std::ostringstream error;
      error << "scene.accuracy_target." << bound.field << " must be positive and finite, got " << *bound.limit;
      throw SceneError(error.str());
    }
  }
  if (!any) {
    throw SceneError("scene.accuracy_target sets no bound; give force_error, force_curve_error or "
                     "cut_position_error_mm (docs/accuracy.md), or drop it and use scene.quality");
  }
  const MeasuredAccuracy* cheapest = nullptr;
  for (const MeasuredAccuracy& measured : MeasuredAccuracies()) {
    if (LeftToUser(measured.resolution)) continue;
    bool meets = true;
    for (const Bound& bound : bounds) meets = meets && (!bound.limit || measured.*bound.error <= *bound.limit);
    if (meets && (!cheapest || measured.relative_cost < cheapest->relative_cost)) cheapest = &measured;
  }
  if (cheapest) return cheapest->resolution;
  // Name the first bound no setting reaches, with the best any setting does.
  for (const Bound& bound : bounds) {
    if (!bound.limit) continue;
    double best = INFINITY;
    for (const MeasuredAccuracy& measured : MeasuredAccuracies()) {
      if (!LeftToUser(measured.resolution)) best = std::min(best, measured.*bound.error);
    }
    if (best > *bound.limit) {
      std::ostringstream error;
      error << "scene.accuracy_target." << bound.field << " " << *bound.limit
            << " is below what any measured setting reaches (best " << best << "; " << AccuracyStudyName()
            << "); loosen it or set scene.mpm yourself";
      throw SceneError(error.str());
    }
  }
  throw SceneError("scene.accuracy_target: no measured setting meets all its bounds at once (" + AccuracyStudyName() +
                   "); loosen one of them");
}

std::string SettingLabel(const MpmResolution& resolution) {
  std::ostringstream label;
  label << "dx " << resolution.dx_m * 1e3 << " mm, " << resolution.particles_per_cell << " ppc, CFL " << resolution.cfl;
  if (resolution.mass_scaling != 1.0) label << ", mass x" << resolution.mass_scaling;
  if (resolution.activity_radius_m != 0.0) label << ", activity " << resolution.activity_radius_m * 1e3 << " mm";
  return label.str();
}

}  // namespace culinarycut
