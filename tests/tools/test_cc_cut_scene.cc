// Cut scenes: JSON parsing (defaults, overrides, errors that name the field) and a small cut run
// end to end.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

#include "tools/cc_cut/cut_scene.h"

namespace culinarycut::mpm {
namespace {

// The message CutSceneFromJson throws for `json_text` ("" when it does not throw).
std::string ErrorFor(const std::string& json_text) {
  try {
    CutSceneFromJson(json_text);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST_CASE("an empty cut scene has the documented defaults", "[mpm][cut_scene]") {
  const CutScene scene = CutSceneFromJson("{}");
  CHECK(scene.food.name == "cucumber");
  CHECK(scene.food.scale == 1.0);
  CHECK(scene.food.position_xy_m == Eigen::Vector2d(0.5, 0.0));
  CHECK_FALSE(scene.food.position_z_m.has_value());
  CHECK(scene.food.yaw_deg == 0.0);
  CHECK(scene.material.preset.empty());
  CHECK_FALSE(scene.material.youngs_modulus_pa.has_value());
  CHECK(scene.solver.dx_m == SolverConfig{}.dx_m);
  CHECK(scene.solver.cfl == SolverConfig{}.cfl);
  CHECK(scene.solver.threads == 1);
  CHECK(scene.particles_per_cell == 8);
  CHECK_FALSE(scene.knife.cut_fraction.has_value());
  CHECK_FALSE(scene.knife.cut_local_x_m.has_value());
  CHECK(scene.knife.descent_speed_m_s == 0.5);
  CHECK(scene.knife.start_above_top_m == 0.006);
  CHECK(scene.knife.end_below_bottom_m == 0.001);
  CHECK_FALSE(scene.knife.apply_speed_resistance);
  CHECK(scene.seed == 0);
  // The material defaults to the food's own preset.
  CHECK(ResolveMaterial(scene).youngs_modulus_pa == MaterialPreset("cucumber").youngs_modulus_pa);
}

TEST_CASE("cut scene fields override the defaults and the preset", "[mpm][cut_scene]") {
  const CutScene scene = CutSceneFromJson(R"({
    "description": "overrides",
    "food": {"name": "banana", "scale": 0.8, "position_m": [0.45, 0.02, 0.05], "yaw_deg": 30},
    "material": {"preset": "generic", "youngs_modulus_pa": 7e4, "poisson_ratio": 0.4,
                 "density_kg_m3": 900, "yield_stress_pa": 1000, "friction_coefficient": 0.2},
    "solver": {"dx_m": 0.005, "particles_per_cell": 4, "cfl": 0.3, "threads": 2,
               "gravity_m_s2": [0, 0, -1],
               "effects": {"damage": false, "friction": false},
               "cutting": {"tip_acceleration_m_s2": 0, "c_hat_min": 0.05}},
    "knife": {"cut_local_x_m": 0.01, "descent_speed_m_s": 0.2, "saw_amplitude_m": 0.003,
              "saw_frequency_hz": 4, "apply_speed_resistance": true, "max_time_s": 2},
    "seed": 7})");
  CHECK(scene.description == "overrides");
  CHECK(scene.food.name == "banana");
  CHECK(scene.food.scale == 0.8);
  CHECK(scene.food.position_z_m.value_or(0.0) == 0.05);
  CHECK(scene.food.yaw_deg == 30.0);
  CHECK(scene.solver.dx_m == 0.005);
  CHECK(scene.particles_per_cell == 4);
  CHECK(scene.solver.cfl == 0.3);
  CHECK(scene.solver.threads == 2);
  CHECK(scene.solver.gravity_m_s2.z() == -1.0);
  CHECK_FALSE(scene.solver.effects.damage);
  CHECK_FALSE(scene.solver.effects.friction);
  CHECK(scene.solver.effects.plasticity);
  CHECK(scene.solver.cutting.tip_acceleration_m_s2 == 0.0);
  CHECK(scene.solver.cutting.c_hat_min == 0.05);
  CHECK(scene.knife.cut_local_x_m.value_or(0.0) == 0.01);
  CHECK(scene.knife.descent_speed_m_s == 0.2);
  CHECK(scene.knife.saw_frequency_hz == 4.0);
  CHECK(scene.knife.apply_speed_resistance);
  CHECK(scene.knife.max_time_s == 2.0);
  CHECK(scene.seed == 7);
  const Material material = ResolveMaterial(scene);
  CHECK(material.name == "generic");
  CHECK(material.youngs_modulus_pa == 7e4);
  CHECK(material.poisson_ratio == 0.4);
  CHECK(material.density_kg_m3 == 900.0);
  CHECK(material.yield_stress_pa == 1000.0);
  CHECK(material.friction_coefficient == 0.2);

  // Written out and read back, the scene is the same.
  const CutScene again = CutSceneFromJson(CutSceneToJson(scene));
  CHECK(CutSceneToJson(again) == CutSceneToJson(scene));
  CHECK(again.knife.cut_local_x_m == scene.knife.cut_local_x_m);
  CHECK(again.material.youngs_modulus_pa == scene.material.youngs_modulus_pa);
}

TEST_CASE("cut scene errors name the field and what is wrong", "[mpm][cut_scene]") {
  struct Case {
    const char* json;
    const char* message;
  };
  const Case cases[] = {
      {R"({"colour": "red"})", "colour: unknown key"},
      {R"({"knife": {"speed_m_s": 1}})", "knife.speed_m_s: unknown key"},
      {R"({"solver": {"cutting": {"band": 1}}})", "solver.cutting.band: unknown key"},
      {R"({"food": {"scale": "big"}})", "food.scale: expected a number, got a string"},
      {R"({"food": {"scale": 0}})", "food.scale: must be in (0, 10], got 0"},
      {R"({"food": {"name": "potato"}})", "food.name: unknown food 'potato'"},
      {R"({"food": {"position_m": [0.5]}})", "food.position_m: expected an array of 2 or 3"},
      {R"({"food": []})", "food: expected an object, got an array"},
      {R"({"material": {"preset": "steel"}})", "material.preset: unknown preset 'steel'"},
      {R"({"material": {"poisson_ratio": 0.5}})", "material.poisson_ratio: must be in (-1, 0.5)"},
      {R"({"material": {"youngs_modulus_pa": -5}})", "material.youngs_modulus_pa: must be > 0"},
      {R"({"solver": {"dx_m": 0}})", "solver.dx_m: must be in (0, 0.1]"},
      {R"({"solver": {"particles_per_cell": 2.5}})",
       "solver.particles_per_cell: expected an integer"},
      {R"({"solver": {"threads": 0}})", "solver.threads: must be >= 1"},
      {R"({"solver": {"j_max": 0.9}})", "solver.j_max: must be > 1"},
      {R"({"solver": {"effects": {"damage": 1}}})",
       "solver.effects.damage: expected true or false"},
      {R"({"solver": {"gravity_m_s2": [0, -9.81]}})",
       "solver.gravity_m_s2: expected an array of 3"},
      {R"({"knife": {"descent_speed_m_s": -1}})", "knife.descent_speed_m_s: must be in (0, 20]"},
      {R"({"knife": {"cut_fraction": 1.5}})", "knife.cut_fraction: must be in (0, 1), got 1.5"},
      {R"({"knife": {"cut_fraction": 0.3, "cut_local_x_m": 0}})",
       "knife.cut_fraction: give either"},
      {R"({"knife": {"cut_local_x_m": 0.5}})", "knife.cut_local_x_m: must lie within the food"},
      {R"({"knife": {"settle_s": -0.1}})", "knife.settle_s: must be >= 0"},
      {R"({"seed": -3})", "seed: must be >= 0"},
      {R"({"food": {)", "invalid JSON"},
      {R"([1, 2])", "scene: expected an object"},
  };
  for (const Case& c : cases) {
    INFO(c.json);
    const std::string message = ErrorFor(c.json);
    CHECK_THAT(message, Catch::Matchers::StartsWith(c.message));
  }
}

TEST_CASE("a cut scene cuts a turned cucumber into two pieces where asked", "[mpm][cut_scene]") {
  CutScene scene = CutSceneFromJson(R"({
    "food": {"name": "cucumber", "scale": 0.4, "yaw_deg": 30},
    "material": {"youngs_modulus_pa": 5e4, "yield_stress_pa": 0},
    "knife": {"cut_fraction": 0.4, "apply_speed_resistance": true}})");
  int calls = 0;
  double last_time_s = 0.0;
  bool ordered = true;
  const CutSceneSummary summary = RunCutScene(scene, [&](const CutStepRecord& record) {
    ordered = ordered && record.step == calls && record.time_s > last_time_s;
    last_time_s = record.time_s;
    ++calls;
  });
  const double dx = scene.solver.dx_m;
  INFO("substeps " << summary.substeps << ", particles " << summary.particles << ", pieces "
                   << summary.pieces.size() << ", peak blade force " << summary.peak_blade_force_n
                   << " N, mismatch " << summary.momentum_mismatch << ", slowest speed "
                   << summary.min_speed_factor);
  CHECK(calls == summary.substeps);
  CHECK(ordered);
  CHECK_FALSE(summary.hit_time_limit);
  CHECK(summary.particles > 1000);
  CHECK(summary.axis_direction.isApprox(
      Eigen::Vector3d(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0), 0.0)));
  REQUIRE(summary.pieces.size() == 2);
  REQUIRE(summary.cut_positions_m.size() == 1);
  CHECK(std::abs(summary.requested_cut_m - 0.4 * summary.food_length_m) < 1e-12);
  CHECK(std::abs(summary.cut_positions_m[0] - summary.requested_cut_m) < 1.5 * dx);
  // The smaller piece is on the near side of the cut.
  CHECK(std::min(summary.pieces[0].volume_m3, summary.pieces[1].volume_m3) <
        0.8 * std::max(summary.pieces[0].volume_m3, summary.pieces[1].volume_m3));
  CHECK(summary.peak_blade_force_n > 0.0);
  CHECK(summary.blade_impulse_n_s.z() > 0.0);  // the food pushes the blade up
  CHECK(summary.momentum_mismatch < 1e-3);
  CHECK(summary.min_speed_factor < 1.0);
  CHECK(summary.min_speed_factor >= scene.knife.min_speed_fraction);
  CHECK(summary.j_min >= scene.solver.j_min);
  CHECK(summary.j_max <= scene.solver.j_max);
  CHECK(summary.particle_steps_per_s > 0.0);
  CHECK(summary.p2g_ms > 0.0);
}

}  // namespace
}  // namespace culinarycut::mpm
