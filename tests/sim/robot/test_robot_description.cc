#include <catch2/catch.hpp>

#include "sim/robot/robot_description.h"
#include "support/robot_fixture.h"

using namespace culinarycut;

TEST_CASE("the Panda description has seven revolute joints with Franka's published limits", "[robot]") {
  const RobotDescription& robot = testing::Panda();
  REQUIRE(robot.dof() == 7);
  CHECK(robot.limits[0].lower_rad == Approx(-2.8973));
  CHECK(robot.limits[3].upper_rad == Approx(-0.0698));
  CHECK(robot.limits[5].upper_rad == Approx(3.7525));
  CHECK(robot.limits[4].max_velocity_rad_s == Approx(2.61));
  CHECK(robot.limits[6].max_effort_nm == Approx(12.0));
  CHECK(robot.links[1].mass_kg == Approx(0.6469));
  // The knife (holder, handle, blade) is merged into link 7.
  CHECK(robot.links[6].mass_kg == Approx(0.7355 + 0.73 + 0.06 + 0.09));
  for (const char* frame : {"panda_link8", "knife_handle", "knife_blade", "knife_tcp"}) {
    CHECK_NOTHROW(robot.TipFrame(frame));
  }
}

TEST_CASE("loading a missing or malformed URDF fails with the file name", "[robot]") {
  CHECK_THROWS_WITH(LoadRobotDescription("/nonexistent/robot.urdf", "tip"), Catch::Contains("/nonexistent/robot.urdf"));
  CHECK_THROWS_WITH(LoadRobotDescription(DefaultRobotUrdfPath(), "no_such_link"), Catch::Contains("no_such_link"));
  CHECK_THROWS_WITH(testing::Panda().TipFrame("nope"), Catch::Contains("knife_tcp"));
}
