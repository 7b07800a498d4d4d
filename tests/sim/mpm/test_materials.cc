#include "sim/mpm/materials.h"

#include <cmath>

#include <catch2/catch.hpp>

namespace culinarycut::mpm {
namespace {

TEST_CASE("every food has a valid preset with a source", "[mpm][materials]") {
  for (const char* food : {"banana", "cucumber", "apple", "peach", "melon", "orange", "strawberry"}) {
    const Material material = MaterialPreset(food);
    INFO(food);
    CHECK_NOTHROW(ValidateMaterial(material));
    CHECK_FALSE(material.source.empty());
  }
  CHECK_THROWS_WITH(MaterialPreset("tofu"), Catch::Contains("presets: apple, cucumber"));
}

TEST_CASE("Lame parameters and wave speed follow E and nu", "[mpm][materials]") {
  Material material = MaterialPreset("apple");  // E 3 MPa, nu 0.17, rho 787
  CHECK(material.shear_modulus_pa() == Approx(3.0e6 / 2.34));
  CHECK(material.lame_lambda_pa() == Approx(3.0e6 * 0.17 / (1.17 * 0.66)));
  // Published: an apple's wave speed is about 64 m/s.
  CHECK(material.dilatational_wave_speed_m_s() == Approx(64.0).epsilon(0.05));
  material.poisson_ratio = 0.5;
  CHECK_THROWS_WITH(ValidateMaterial(material), Catch::Contains("poisson_ratio"));
}

}  // namespace
}  // namespace culinarycut::mpm
