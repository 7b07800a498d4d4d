#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "sim/world/scene_config.h"

using namespace culinarycut;

TEST_CASE("the default scene config is valid", "[scene]") { CHECK_FALSE(ValidateSceneConfig(SceneConfig{}).has_value()); }

TEST_CASE("bad scene configs name the field at fault", "[scene]") {
  auto error_for = [](auto mutate) {
    SceneConfig config;
    mutate(config);
    const auto error = ValidateSceneConfig(config);
    return error ? *error : std::string();
  };
  CHECK_THAT(error_for([](SceneConfig& c) { c.robot.control_frequency_hz = 1e-9; }), Catch::Contains("control_frequency_hz"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.robot.control_frequency_hz = std::nan(""); }), Catch::Contains("control_frequency_hz"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.robot.physics_frequency_hz = 333; }), Catch::Contains("integer multiple"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.robot.physics_frequency_hz = 100; c.robot.control_frequency_hz = 100; }),
             Catch::Contains("at least 500"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.robot.joint_stiffness_per_s = -1; }), Catch::Contains("joint_stiffness"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.scene = "garden"; }), Catch::Contains("scene.scene"));
  CHECK_THAT(error_for([](SceneConfig& c) { c.quality = "ultra"; }), Catch::Contains("scene.quality"));
}
