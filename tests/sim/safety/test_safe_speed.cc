// The paper's safe velocity: v_safe keeps F_hat(v_safe) <= F_max and is the largest such speed within
// the stated tolerance, for synthetic posynomials with a known answer; 0 and the range's top at the ends.
#include <catch2/catch.hpp>

#include <cmath>

#include "force_model_fixture.h"
#include "sim/safety/safe_speed.h"

using namespace culinarycut;
using namespace culinarycut::safety;

namespace {

ForceModel Model(const std::vector<testing::TestTerm>& terms) {
  return ParseForceModel(testing::ForceModelDocument(terms).dump());
}

const CutMaterial kCucumber{2.0, 20.0, 200.0, 0.05};

}  // namespace

TEST_CASE("v_safe is feasible and maximal within the tolerance for synthetic posynomials", "[safety][safe_speed]") {
  // F = a v^p E L + b G L: v* = ((F_max - b G L) / (a E L))^(1/p)
  for (const double power : {0.5, 1.0, 2.0}) {
    for (const double max_force_n : {15.0, 40.0, 90.0}) {
      const ForceModel model = Model({{30.0, {power, 1, 0, 0, 1}}, {1.0, {0, 0, 0, 1, 1}}});
      const double base_n = 1.0 * 200.0 * 0.05;
      const double expected_m_s = std::pow((max_force_n - base_n) / (30.0 * 2.0 * 0.05), 1.0 / power);
      const SafeSpeed safe = SafeCuttingSpeed(model, kCucumber, max_force_n);
      INFO("power " << power << ", F_max " << max_force_n << " N, expected " << expected_m_s << " m/s");
      REQUIRE(expected_m_s > 0.02);  // inside the speed range: no out-of-range factor
      CHECK(PredictPeakForce(model, safe.v_safe_m_s, kCucumber).force_n <= max_force_n);
      if (expected_m_s < 4.0) {
        CHECK(safe.v_safe_m_s <= expected_m_s);
        CHECK(safe.v_safe_m_s >= expected_m_s - kSafeSpeedToleranceMS);
        CHECK(PredictPeakForce(model, safe.v_safe_m_s + kSafeSpeedToleranceMS, kCucumber).force_n > max_force_n);
      } else {
        CHECK(safe.v_safe_m_s == 4.0);  // the top of the validated range
      }
      CHECK(safe.predicted_force_n == Approx(PredictPeakForce(model, safe.v_safe_m_s, kCucumber).force_n));
    }
  }
}

TEST_CASE("v_safe is 0 when a still knife is already predicted past F_max", "[safety][safe_speed]") {
  const ForceModel model = Model({{1.0, {0, 0, 0, 1, 1}}, {5.0, {1, 0, 0, 0, 0}}});  // 10 N at rest
  CHECK(SafeCuttingSpeed(model, kCucumber, 8.0).v_safe_m_s == 0.0);
}

TEST_CASE("below the speed range the out-of-range factor applies and v_safe is still maximal", "[safety][safe_speed]") {
  // F = 100 v L = 5 v: F(0.02) = 0.1 N. F_max 0.09 N: unfactored v* = 0.018 is below the range (0.02), so
  // the factor 1.5 applies there: v* = 0.09 / (1.5 * 5) = 0.012.
  const ForceModel model = Model({{100.0, {1, 0, 0, 0, 1}}});
  const SafeSpeed safe = SafeCuttingSpeed(model, kCucumber, 0.09);
  CHECK(safe.out_of_range);
  CHECK(safe.v_safe_m_s == Approx(0.012).margin(kSafeSpeedToleranceMS));
  CHECK(safe.v_safe_m_s <= 0.012);
}
