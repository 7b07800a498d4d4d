// cc-cut's scene file: the server's SceneSpec block with cc-cut's knife and solver blocks (defaults,
// overrides, errors that name the field), the food built as a server session builds it, and a small
// cut run end to end.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

#include "server/wire/scene.h"
#include "sim/mpm/materials.h"
#include "sim/task/object_box.h"
#include "sim/world/model.h"
#include "support/robot_fixture.h"
#include "tools/cc_cut/cut_model.h"
#include "tools/cc_cut/cut_run.h"
#include "tools/cc_cut/cut_scene.h"

namespace culinarycut::cc_cut {
namespace {

// A small softened cucumber at the draft grid: compiles in milliseconds.
const std::string kSmallScene =
    R"("scene": {"effects": {"mpm": true}, "quality": "draft", "objects": [{"food": "cucumber",
        "scale": 0.4, "material_overrides": {"youngs_modulus_pa": 5e4}}]})";

// The message reading and compiling `json_text` throws ("" when neither throws).
std::string ErrorFor(const std::string& json_text) {
  try {
    CompileCut(CutSceneFromJson(json_text));
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST_CASE("a cc-cut scene with one food has the documented defaults", "[cc_cut][cut_scene]") {
  const CutScene scene =
      CutSceneFromJson(R"({"scene": {"effects": {"mpm": true}, "objects": [{"food": "cucumber"}]}})");
  CHECK(scene.description.empty());
  CHECK(scene.scene.objects(0).scale() == 0.0);  // SceneSpec: 0 means 1
  CHECK(scene.scene.seed() == 0);
  CHECK_FALSE(scene.solver.threads.has_value());
  CHECK_FALSE(scene.solver.grid_damping_per_s.has_value());
  CHECK_FALSE(scene.solver.two_sided_blade.has_value());
  CHECK_FALSE(scene.solver.cutting.v_hat.has_value());
  CHECK_FALSE(scene.knife.cut_fraction.has_value());
  CHECK_FALSE(scene.knife.cut_from_centre_m.has_value());
  CHECK(scene.knife.descent_speed_m_s == 0.5);
  CHECK(scene.knife.start_above_top_m == 0.006);
  CHECK(scene.knife.end_below_bottom_m == 0.001);
  CHECK_FALSE(scene.knife.apply_speed_resistance);

  const CutModel model = CompileCut(scene);
  CHECK(model.config.foods.at(0).scale == 1.0);
  // The standard preset's resolution and the food's own material preset.
  CHECK(model.food.resolution.dx_m == 0.004);
  CHECK(model.food.resolution.particles_per_cell == 6);
  CHECK(model.food.resolution.cfl == 0.8);
  const mpm::Material& material = model.food.solver->materials.at(0);
  CHECK(material.youngs_modulus_pa == mpm::MaterialPreset("cucumber").youngs_modulus_pa);
  // SceneSpec's default pose: long axis along world y, resting on the board at its centre.
  const task::ObjectBox& food = model.food.objects.at(0);
  CHECK(food.pose.linear().col(0).isApprox(Eigen::Vector3d::UnitY()));
  CHECK(food.pose.translation().head<2>().isApprox(model.layout.board_center_m.head<2>()));
  const double board_top_m = model.layout.board_center_m.z() + 0.5 * model.layout.board_size_m.z();
  CHECK(task::BottomZ(food) == Approx(board_top_m));
  // The server's solver: only the declared effects, a two-sided blade.
  const mpm::SolverConfig& solver = model.food.solver->config;
  CHECK_FALSE(solver.effects.damage);
  CHECK_FALSE(solver.effects.force_sensing);
  CHECK(solver.effects.two_sided_blade);
  CHECK(model.food.initial_particles.size() > 1000);
}

TEST_CASE("cc-cut scene fields override the defaults and the preset", "[cc_cut][cut_scene]") {
  // The banana turned 30 degrees about z from world x.
  const CutScene scene = CutSceneFromJson(R"({
    "description": "overrides",
    "scene": {
      "effects": {"mpm": true, "plasticity": true, "damage": true, "force_sensing": true},
      "objects": [{"food": "banana", "scale": 0.8,
                   "pose": {"position": [0.45, 0.02, 0.05],
                            "quaternion": [0.9659258262890683, 0, 0, 0.25881904510252074]},
                   "material": "generic",
                   "material_overrides": {"youngs_modulus_pa": 7e4, "poisson_ratio": 0.4,
                                          "density_kg_m3": 900, "yield_stress_pa": 1000,
                                          "friction_coefficient": 0.2}}],
      "mpm": {"dx": 0.005, "particlesPerCell": 4, "cfl": 0.3},
      "seed": 7},
    "solver": {"threads": 2, "gravity_m_s2": [0, 0, -1], "grid_damping_per_s": 0,
               "two_sided_blade": false, "cutting": {"tip_acceleration_m_s2": 0, "c_hat_min": 0.05}},
    "knife": {"cut_from_centre_m": 0.01, "descent_speed_m_s": 0.2, "saw_amplitude_m": 0.003,
              "saw_frequency_hz": 4, "apply_speed_resistance": true, "max_time_s": 2}})");
  CHECK(scene.description == "overrides");
  CHECK(scene.knife.cut_from_centre_m.value_or(0.0) == 0.01);
  CHECK(scene.knife.descent_speed_m_s == 0.2);
  CHECK(scene.knife.saw_frequency_hz == 4.0);
  CHECK(scene.knife.apply_speed_resistance);
  CHECK(scene.knife.max_time_s == 2.0);

  const CutModel model = CompileCut(scene);
  const FoodConfig& food = model.config.foods.at(0);
  CHECK(food.food == "banana");
  CHECK(food.scale == 0.8);
  CHECK(model.food.objects.at(0).pose.translation().isApprox(Eigen::Vector3d(0.45, 0.02, 0.05)));
  CHECK(model.food.objects.at(0).pose.linear().col(0).isApprox(
      Eigen::Vector3d(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0), 0.0)));
  CHECK(model.config.seed == 7);
  CHECK(model.food.resolution.dx_m == 0.005);
  CHECK(model.food.resolution.particles_per_cell == 4);
  CHECK(model.food.resolution.cfl == 0.3);
  const mpm::SolverConfig& solver = model.food.solver->config;
  CHECK(solver.dx_m == 0.005);
  CHECK(solver.threads == 2);
  CHECK(solver.gravity_m_s2.z() == -1.0);
  CHECK(solver.grid_damping_per_s == 0.0);
  CHECK_FALSE(solver.effects.two_sided_blade);
  CHECK_FALSE(solver.effects.friction);  // not declared
  CHECK(solver.effects.damage);
  CHECK(solver.effects.plasticity);
  CHECK(solver.cutting.tip_acceleration_m_s2 == 0.0);
  CHECK(solver.cutting.c_hat_min == 0.05);
  CHECK(solver.cutting.v_hat == mpm::CuttingParameters{}.v_hat);  // not overridden
  const mpm::Material& material = model.food.solver->materials.at(0);
  CHECK(material.name == "generic");
  CHECK(material.youngs_modulus_pa == 7e4);
  CHECK(material.poisson_ratio == 0.4);
  CHECK(material.density_kg_m3 == 900.0);
  CHECK(material.yield_stress_pa == 1000.0);
  CHECK(material.friction_coefficient == 0.2);

  // Written out and read back, the scene is the same.
  const CutScene again = CutSceneFromJson(CutSceneToJson(scene));
  CHECK(CutSceneToJson(again) == CutSceneToJson(scene));
  CHECK(again.knife.cut_from_centre_m == scene.knife.cut_from_centre_m);
  CHECK(again.solver.gravity_m_s2 == scene.solver.gravity_m_s2);
  CHECK(again.scene.objects(0).material_overrides().at("youngs_modulus_pa") == 7e4);
  CHECK(again.scene.seed() == 7);
}

TEST_CASE("cc-cut builds the food a server session builds", "[cc_cut][cut_scene]") {
  const CutScene scene = CutSceneFromJson("{" + kSmallScene + "}");
  const CutModel cut = CompileCut(scene);
  const auto session = CompileModel(server::SceneFromWire(scene.scene), testing::Panda());
  REQUIRE(session->food.has_value());
  const FoodModel& food = *session->food;
  CHECK(cut.food.initial_particles.position == food.initial_particles.position);
  CHECK(cut.food.initial_particles.mass == food.initial_particles.mass);
  CHECK(cut.food.objects.at(0).pose.isApprox(food.objects.at(0).pose));
  CHECK(cut.food.resolution.dx_m == food.resolution.dx_m);
  CHECK(cut.food.solver->materials.at(0).youngs_modulus_pa == food.solver->materials.at(0).youngs_modulus_pa);
  CHECK(cut.food.solver->config.grid_damping_per_s == food.solver->config.grid_damping_per_s);
  CHECK(mpm::StableTimestep(*cut.food.solver) == mpm::StableTimestep(*food.solver));
  CHECK(cut.layout.board_center_m == session->layout.board_center_m);
  CHECK(cut.food.topology.link_distance_m == food.topology.link_distance_m);
}

TEST_CASE("cc-cut scene errors name the field and what is wrong", "[cc_cut][cut_scene]") {
  struct Case {
    std::string json;
    const char* message;
  };
  const std::string small = kSmallScene;
  const std::string food = R"({"scene": {"effects": {"mpm": true}, "objects": [{"food": "cucumber", )";
  const Case cases[] = {
      {R"({"colour": "red"})", "colour: unknown key"},
      {R"({"food": {"name": "cucumber"}})", "food: unknown key (the food is scene.objects[0]"},
      {R"({"knife": {"speed_m_s": 1}})", "knife.speed_m_s: unknown key"},
      {R"({"solver": {"dx_m": 0.004}})", "solver.dx_m: unknown key (use scene.mpm.dx)"},
      {R"({"solver": {"cutting": {"band": 1}}})", "solver.cutting.band: unknown key"},
      {R"({"scene": {"colour": 1}})", "scene.colour: unknown field"},
      {food + R"("size": 1}]}})", "scene.objects[0].size: unknown field"},
      {food + R"("scale": "big"}]}})", "scene.objects[0].scale: expected a number, got a string"},
      {food + R"("scale": 20}]}})", "scene.objects[0].scale must be in [0.001, 10]"},
      {R"({"scene": {"effects": {"mpm": true}, "objects": [{"food": "potato"}]}})",
       "scene.objects[0]: MakeFoodShape: unknown food 'potato'"},
      {food + R"("pose": {"position": [0.5]}}]}})", "scene.objects[0].pose.position must have 3 values"},
      {food + R"("pose": {"position": [5, 0]}}]}})", "scene.objects[0].pose.position puts the food off the table"},
      {R"({"scene": {"objects": [[]]}})", "scene.objects[0]: expected an object, got an array"},
      {food + R"("material": "steel"}]}})", "scene.objects[0].material: unknown material preset 'steel'"},
      {food + R"("material_overrides": {"poisson_ratio": 0.5}}]}})",
       "scene.objects[0].material_overrides: material 'cucumber': poisson_ratio must lie in (-1, 0.5)"},
      {food + R"("material_overrides": {"youngs_modulus_pa": -5}}]}})",
       "scene.objects[0].material_overrides: material 'cucumber': youngs_modulus_pa must be in"},
      {food + R"("material_overrides": {"youngs": 5}}]}})", "scene.objects[0].material_overrides: unknown key 'youngs'"},
      {food + R"("scale": 0.4}], "mpm": {"dx": 0.5}}})", "scene.mpm.dx must be in [0.001, 0.02] m"},
      {R"({"scene": {"mpm": {"particles_per_cell": 2.5}}})", "scene.mpm.particles_per_cell: expected an integer"},
      {food + R"("scale": 0.4}], "quality": "ultra"}})", "scene.quality must be \"draft\", \"standard\" or \"fine\""},
      {R"({"scene": {"effects": {"damage": 1}}})", "scene.effects.damage: expected true or false"},
      {R"({"scene": {"objects": [{"food": "cucumber"}]}})", "scene.objects needs scene.effects.mpm = true"},
      {R"({"scene": {"seed": -3}})", "scene.seed: expected an integer >= 0"},
      {R"({})", "scene.objects: cc-cut cuts one food object; give exactly one, got 0"},
      {R"({"scene": {"effects": {"mpm": true}, "objects": [{"food": "cucumber"}, {"food": "apple"}]}})",
       "scene.objects: cc-cut cuts one food object; give exactly one, got 2"},
      {food + R"("scale": 0.4}], "robot": {"joint_stiffness": 10}}})", "scene.robot: cc-cut has no robot"},
      {food + R"("scale": 0.4}], "cameras": [{"name": "front"}]}})", "scene.cameras: cc-cut renders nothing"},
      {food + R"("scale": 0.4}], "task": {"cut_state": "middle"}}})", "scene.task: cc-cut has no task"},
      {"{" + small + R"(, "solver": {"threads": 0}})", "solver.threads: must be in [1, 1024], got 0"},
      {"{" + small + R"(, "solver": {"j_max": 0.9}})", "solver.j_max: must be > 1"},
      {"{" + small + R"(, "solver": {"gravity_m_s2": [0, -9.81]}})", "solver.gravity_m_s2: expected an array of 3"},
      {"{" + small + R"(, "solver": {"two_sided_blade": 1}})", "solver.two_sided_blade: expected true or false"},
      {"{" + small + R"(, "knife": {"descent_speed_m_s": -1}})", "knife.descent_speed_m_s: must be in (0, 20]"},
      {"{" + small + R"(, "knife": {"cut_fraction": 1.5}})", "knife.cut_fraction: must be in (0, 1), got 1.5"},
      {"{" + small + R"(, "knife": {"cut_fraction": 0.3, "cut_from_centre_m": 0}})", "knife.cut_fraction: give either"},
      {"{" + small + R"(, "knife": {"cut_from_centre_m": 0.5}})", "knife.cut_from_centre_m: must lie within the food"},
      {"{" + small + R"(, "knife": {"settle_s": -0.1}})", "knife.settle_s: must be >= 0"},
      {"{" + small + R"(, "knife": {"cut_local_x_m": 0}})", "knife.cut_local_x_m: unknown key (use cut_from_centre_m"},
      {R"({"scene": {"objects": [{)", "invalid JSON"},
      {R"([1, 2])", "top level: expected an object"},
      {R"({"scene": 3})", "scene: expected an object, got a number"},
  };
  for (const Case& c : cases) {
    INFO(c.json);
    CHECK_THAT(ErrorFor(c.json), Catch::Matchers::StartsWith(c.message));
  }
  CHECK(ErrorFor("{" + small + "}").empty());
}

TEST_CASE("a cc-cut run cuts a turned cucumber into two pieces where asked", "[cc_cut][cut_scene]") {
  // The cucumber's long axis 30 degrees from world x; the task's long axis runs from its left end
  // (+y side) to its right end. Soft and weak (E 50 kPa, G 125 J/m^2: the measured toughness, not the
  // calibrated edge toughness, which a food this soft squashes under rather than parts).
  const CutModel model = CompileCut(CutSceneFromJson(R"({
    "scene": {
      "effects": {"mpm": true, "plasticity": true, "damage": true, "friction": true, "force_sensing": true},
      "objects": [{"food": "cucumber", "scale": 0.4,
                   "pose": {"position": [0.5, 0.0], "quaternion": [0.9659258262890683, 0, 0, 0.25881904510252074]},
                   "material_overrides": {"youngs_modulus_pa": 5e4, "yield_stress_pa": 0,
                                          "fracture_toughness_j_m2": 125}}]},
    "knife": {"cut_fraction": 0.4, "apply_speed_resistance": true}})"));
  int calls = 0;
  double last_time_s = 0.0;
  bool ordered = true;
  const CutSummary summary = RunCut(model, [&](const CutStepRecord& record) {
    ordered = ordered && record.step == calls && record.time_s > last_time_s;
    last_time_s = record.time_s;
    ++calls;
  });
  const mpm::SolverConfig& solver = model.food.solver->config;
  const double dx = solver.dx_m;
  INFO("substeps " << summary.substeps << ", particles " << summary.particles << ", pieces "
                   << summary.pieces.size() << ", peak blade force " << summary.peak_blade_force_n
                   << " N, mismatch " << summary.momentum_mismatch << ", slowest speed "
                   << summary.min_speed_factor);
  CHECK(calls == summary.substeps);
  CHECK(ordered);
  CHECK_FALSE(summary.hit_time_limit);
  CHECK(summary.particles > 1000);
  CHECK(summary.axis_direction.isApprox(
      Eigen::Vector3d(-std::cos(M_PI / 6.0), -std::sin(M_PI / 6.0), 0.0)));
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
  CHECK(summary.min_speed_factor >= model.knife.min_speed_fraction);
  // J is clamped in float: within float rounding of the bounds.
  CHECK(summary.j_min >= solver.j_min - 1e-6);
  CHECK(summary.j_max <= solver.j_max + 1e-6);
  CHECK(summary.particle_steps_per_s > 0.0);
  CHECK(summary.p2g_ms > 0.0);
}

}  // namespace
}  // namespace culinarycut::cc_cut

namespace culinarycut::cc_cut {
namespace {

TEST_CASE("cc-cut cuts a reference specimen of a food's material: its shape replaces the food's",
          "[cc_cut][cut_scene][specimen]") {
  const std::string specimen = R"(, "specimen": {"shape": "box", "size_m": [0.06, 0.05, 0.03]})";
  const CutScene scene = CutSceneFromJson("{" + kSmallScene + specimen + "}");
  REQUIRE(scene.specimen.has_value());
  const CutModel cut = CompileCut(scene);
  // The box's extent, the food's material, and a box's particle count (volume / dx^3 * ppc).
  CHECK(cut.food.objects.at(0).extent_m.isApprox(Eigen::Vector3d(0.06, 0.05, 0.03)));
  CHECK(cut.food.solver->materials.at(0).youngs_modulus_pa == 5e4);
  const double dx = cut.food.resolution.dx_m;
  const double cells = 0.06 * 0.05 * 0.03 / (dx * dx * dx);
  CHECK(static_cast<double>(cut.food.initial_particles.size()) ==
        Approx(cells * cut.food.resolution.particles_per_cell).epsilon(0.35));
  // The file round-trips with its specimen.
  const CutScene again = CutSceneFromJson(CutSceneToJson(scene));
  REQUIRE(again.specimen.has_value());
  CHECK(again.specimen->kind == "box");
  CHECK(again.specimen->size_m.isApprox(scene.specimen->size_m));
}

TEST_CASE("a bad specimen is refused naming the field", "[cc_cut][cut_scene][specimen]") {
  CHECK_THAT(ErrorFor("{" + kSmallScene + R"(, "specimen": {"shape": "cone", "size_m": [0.1, 0.1, 0.05]}})"),
             Catch::Contains("specimen") && Catch::Contains("unknown specimen 'cone'"));
  CHECK_THAT(ErrorFor("{" + kSmallScene + R"(, "specimen": {"shape": "half_cylinder", "size_m": [0.1, 0.1, 0.1]}})"),
             Catch::Contains("twice its height"));
  CHECK_THAT(ErrorFor("{" + kSmallScene + R"(, "specimen": {"shape": "box"}})"), Catch::Contains("specimen.size_m"));
  CHECK_THAT(ErrorFor("{" + kSmallScene + R"(, "specimen": {"shape": "box", "size_m": [0.1, 0.1], "x": 1}})"),
             Catch::Contains("specimen.size_m"));
}

}  // namespace
}  // namespace culinarycut::cc_cut
