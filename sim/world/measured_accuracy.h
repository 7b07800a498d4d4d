// What the accuracy study (bench/accuracy_cost.py, docs/accuracy.md) measured for each setting of the
// MPM's quality knobs: its worst error over the study's cuts against the reference, and its cost. The
// presets' expected errors, and the setting an accuracy target resolves to, come from here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/world/quality_preset.h"
#include "sim/world/scene_config.h"

namespace culinarycut {

struct MeasuredAccuracy {
  MpmResolution resolution;
  double peak_force_error = 0.0;       // peak (5 ms window) blade force, relative to the reference
  double mean_force_error = 0.0;       // mean blade force over the middle of the cut, relative
  double force_curve_error = 0.0;      // force-depth curve, relative L2
  double cut_position_error_mm = 0.0;  // where the cut lands (mm)
  double relative_cost = 0.0;          // the study's wall time over the standard preset's, same cuts
};

// Where the numbers come from: the study's page, date, cuts and reference.
std::string AccuracyStudyName();

// Every setting the study measured except its reference (generated: measured_accuracy_table.cc).
const std::vector<MeasuredAccuracy>& MeasuredAccuracies();

// The study's numbers for exactly this setting, or nothing when it was not measured.
std::optional<MeasuredAccuracy> FindMeasuredAccuracy(const MpmResolution& resolution);

// The cheapest measured real-mass setting without activity whose every error meets the target's
// bounds (mass scaling and activity are left to the user: their price depends on the cut). Throws
// SceneError naming the field when a bound is not positive and finite, when none is set, or when no
// measured setting reaches it.
MpmResolution CheapestSettingMeeting(const AccuracyTargetConfig& target);

// "dx 4 mm, 8 ppc, CFL 0.4" (and ", mass x16", ", activity 20 mm" when set), as the study labels its settings.
std::string SettingLabel(const MpmResolution& resolution);

}  // namespace culinarycut
