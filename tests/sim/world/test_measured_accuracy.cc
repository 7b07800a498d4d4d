// The presets and accuracy targets answer from the accuracy study's measurements (docs/accuracy.md).
#include <catch2/catch.hpp>

#include "sim/world/measured_accuracy.h"
#include "sim/world/model.h"

namespace culinarycut {
namespace {

MeasuredAccuracy Measured(const MpmResolution& resolution) {
  const std::optional<MeasuredAccuracy> measured = FindMeasuredAccuracy(resolution);
  REQUIRE(measured.has_value());
  return *measured;
}

TEST_CASE("draft and standard are measured settings; standard is as accurate as the old one for less", "[world][quality]") {
  const MeasuredAccuracy draft = Measured(ResolveMpmResolution("draft", std::nullopt, {}));
  const MeasuredAccuracy standard = Measured(ResolveMpmResolution("standard", std::nullopt, {}));
  CHECK(standard.relative_cost == Approx(1.0));
  CHECK(draft.relative_cost < 0.25 * standard.relative_cost);  // at least 4x cheaper
  CHECK(draft.peak_force_error > standard.peak_force_error);
  // The standard preset until the study: dx 4 mm, 8 ppc, CFL 0.2.
  const MpmResolution previous{0.004, 8, 0.2};
  const MeasuredAccuracy old_standard = Measured(previous);
  CHECK(old_standard.relative_cost > 1.5);
  CHECK(standard.peak_force_error <= old_standard.peak_force_error);
  CHECK(standard.force_curve_error <= old_standard.force_curve_error);
  // Within the 0.05 mm the study resolves (docs/accuracy.md's rule).
  CHECK(standard.cut_position_error_mm <= old_standard.cut_position_error_mm + 0.05);
  CHECK_FALSE(FindMeasuredAccuracy(ResolveMpmResolution("fine", std::nullopt, {})).has_value());
}

TEST_CASE("an accuracy target resolves to the cheapest real-mass setting that meets every bound", "[world][quality]") {
  for (const double bound : {0.05, 0.06, 0.08, 0.1, 0.2, 0.3}) {
    AccuracyTargetConfig target;
    target.force_error = bound;
    const MpmResolution chosen = ResolveMpmResolution("standard", target, {});
    const MeasuredAccuracy measured = Measured(chosen);
    INFO("force_error " << bound << " -> " << SettingLabel(chosen));
    CHECK(measured.peak_force_error <= bound);
    CHECK(chosen.mass_scaling == 1.0);
    for (const MeasuredAccuracy& other : MeasuredAccuracies()) {
      if (other.resolution.mass_scaling == 1.0 && other.peak_force_error <= bound) {
        CHECK(measured.relative_cost <= other.relative_cost);
      }
    }
  }
  AccuracyTargetConfig loose;
  loose.force_error = 0.3;
  loose.cut_position_error_mm = 1.0;
  CHECK(ResolveMpmResolution("standard", loose, {}).dx_m == Approx(0.008));  // the draft's grid
  // Two bounds together: both hold.
  AccuracyTargetConfig both;
  both.force_error = 0.1;
  both.force_curve_error = 0.1;
  const MeasuredAccuracy chosen = Measured(ResolveMpmResolution("draft", both, {}));
  CHECK(chosen.peak_force_error <= 0.1);
  CHECK(chosen.force_curve_error <= 0.1);
}

TEST_CASE("explicit mpm values override the target's setting one by one", "[world][quality]") {
  AccuracyTargetConfig target;
  target.force_error = 0.3;
  MpmResolutionConfig overrides;
  overrides.particles_per_cell = 8;
  const MpmResolution resolved = ResolveMpmResolution("standard", target, overrides);
  CHECK(resolved.dx_m == Approx(0.008));
  CHECK(resolved.particles_per_cell == 8);
}

TEST_CASE("an unreachable, empty or negative accuracy target is refused naming the field", "[world][quality]") {
  AccuracyTargetConfig tight;
  tight.force_error = 0.001;
  CHECK_THROWS_WITH(ResolveMpmResolution("standard", tight, {}),
                    Catch::Contains("scene.accuracy_target.force_error 0.001 is below what any measured setting"));
  CHECK_THROWS_WITH(ResolveMpmResolution("standard", AccuracyTargetConfig{}, {}),
                    Catch::Contains("scene.accuracy_target sets no bound"));
  AccuracyTargetConfig negative;
  negative.cut_position_error_mm = -1.0;
  CHECK_THROWS_WITH(ResolveMpmResolution("standard", negative, {}),
                    Catch::Contains("scene.accuracy_target.cut_position_error_mm must be positive"));
  AccuracyTargetConfig conflicting;  // each reachable alone, not together
  conflicting.force_error = 0.035;
  conflicting.cut_position_error_mm = 0.03;
  CHECK_THROWS_WITH(ResolveMpmResolution("standard", conflicting, {}),
                    Catch::Contains("no measured setting meets all its bounds at once"));
}

}  // namespace
}  // namespace culinarycut
