#include <catch2/catch.hpp>

#include "sim/core/assets.h"
#include "sim/render/food_palette.h"
#include "sim/render/render_error.h"
#include "sim/render/robot_visuals.h"
#include "sim/render/scene_geometry.h"
#include "sim/robot/robot_description.h"
#include "sim/robot/robot_visuals_from_urdf.h"

namespace culinarycut::render {
namespace {

const std::string kDataDir = CULINARYCUT_RENDER_TEST_DATA;

TEST_CASE("Panda visuals map onto the same movable links as the robot description") {
  const std::string urdf = AssetsDir() + "/panda/panda_knife.urdf";
  const RobotVisuals visuals = BuildRobotVisuals(LoadRobotDescription(urdf, "knife_tcp").visuals);
  const RobotDescription robot = LoadRobotDescription(urdf, "knife_tcp");
  REQUIRE(visuals.pose_count() == robot.dof() + 1);
  CHECK(visuals.owner_names[0] == robot.base.name);
  for (int i = 0; i < robot.dof(); ++i) CHECK(visuals.owner_names[i + 1] == robot.links[i].name);
  // Knife visuals ride on the last link with the fixed offsets the description merged in.
  int knife_parts = 0;
  for (const RobotVisualPart& part : visuals.parts) {
    if (part.link_name.rfind("knife", 0) != 0) {
      CHECK(part.segment == kRobotSegment);
      continue;
    }
    ++knife_parts;
    CHECK(part.segment == kKnifeSegment);
    CHECK(part.owner == robot.dof());
  }
  CHECK(knife_parts == 3);
  const auto& [owner, blade_in_owner] = visuals.link_frames.at("knife_blade");
  CHECK(owner == robot.dof());
  CHECK(blade_in_owner.isApprox(robot.TipFrame("knife_blade"), 1e-12));
  const auto& flange = visuals.link_frames.at("panda_link8");
  CHECK(flange.second.translation().isApprox(Eigen::Vector3d(0, 0, 0.107)));
}

TEST_CASE("Mesh visuals load through assimp with their scale, colour and fixed offsets") {
  const RobotVisuals visuals = BuildRobotVisuals(ReadRobotVisuals(kDataDir + "/mesh_arm.urdf"));
  REQUIRE(visuals.owner_names == std::vector<std::string>{"base", "arm"});
  const RobotVisualPart* tool = nullptr;
  const RobotVisualPart* tip = nullptr;
  for (const RobotVisualPart& part : visuals.parts) {
    if (part.link_name == "tool") tool = &part;
    if (part.link_name == "knife_tip") tip = &part;
  }
  REQUIRE(tool != nullptr);
  REQUIRE(tip != nullptr);
  CHECK(tool->owner == 1);
  CHECK(tool->in_owner.translation().isApprox(Eigen::Vector3d(0, 0, 0.4)));
  CHECK(tool->mesh.triangle_count() == 4);
  float max_z = 0.0f;
  for (std::size_t v = 0; v < tool->mesh.vertex_count(); ++v) max_z = std::max(max_z, tool->mesh.positions_m[3 * v + 2]);
  CHECK(max_z == Approx(0.2f));
  CHECK(tool->material.color.x() == Approx(1.0f));
  CHECK(tool->material.color.y() == Approx(0.0f));
  CHECK(tip->segment == kKnifeSegment);
  CHECK(tip->in_owner.translation().isApprox(Eigen::Vector3d(0, 0, 0.45)));
}

TEST_CASE("Unreadable robot and mesh files give an error naming the file") {
  CHECK_THROWS_WITH(ReadRobotVisuals(kDataDir + "/missing.urdf"), Catch::Contains("missing.urdf"));
  RobotVisualDescription missing_mesh;
  missing_mesh.owner_names = {"base"};
  missing_mesh.visuals.emplace_back();
  missing_mesh.visuals.back().shape.kind = VisualShape::Kind::kMesh;
  missing_mesh.visuals.back().shape.mesh_path = "/nonexistent/robot.stl";
  CHECK_THROWS_AS(BuildRobotVisuals(missing_mesh), RenderError);
  CHECK_THROWS_WITH(BuildRobotVisuals(missing_mesh), Catch::Contains("/nonexistent/robot.stl"));
}

TEST_CASE("Scenes and food palettes refuse unknown names and list the known ones") {
  const SceneLayout layout;
  for (const std::string& scene : SceneNames()) {
    const SceneGeometry geometry = BuildSceneGeometry(scene, layout);
    int boards = 0;
    for (const ScenePart& part : geometry.parts) boards += part.segment == kBoardSegment;
    CHECK(boards == 1);
  }
  CHECK_THROWS_WITH(BuildSceneGeometry("garden", layout), Catch::Contains("kitchen"));
  CHECK(FoodPaletteNames().size() == 7);
  for (const std::string& food : FoodPaletteNames()) {
    // A cut must be visible: flesh differs from skin.
    CHECK((FoodPalette(food).skin - FoodPalette(food).flesh).norm() > 0.1f);
  }
  CHECK_THROWS_WITH(FoodPalette("durian"), Catch::Contains("cucumber"));
}

}  // namespace
}  // namespace culinarycut::render
