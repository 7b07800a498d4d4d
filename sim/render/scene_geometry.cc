#include "sim/render/scene_geometry.h"

#include <cmath>

#include "sim/render/primitive_meshes.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

Eigen::Vector3f Srgb(int r, int g, int b) {
  auto linear = [](int c) { return std::pow(c / 255.0f, 2.2f); };
  return {linear(r), linear(g), linear(b)};
}

Material Make(MaterialKind kind, Eigen::Vector3f color, Eigen::Vector3f second = Eigen::Vector3f::Zero(),
              float specular = 0.08f, float shininess = 24.0f, float pattern_scale_m = 0.1f) {
  Material material;
  material.kind = kind;
  material.color = color;
  material.second_color = second;
  material.specular = specular;
  material.shininess = shininess;
  material.pattern_scale_m = pattern_scale_m;
  return material;
}

// An axis-aligned box given by its min and max corners (m).
void AddBox(SceneGeometry* scene, const std::string& name, const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m,
            const Material& material, bool casts_shadow = false, int segment = kBackgroundSegment) {
  ScenePart part;
  part.name = name;
  part.mesh = MakeBoxMesh(max_m - min_m);
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = 0.5 * (min_m + max_m);
  TransformMesh(at, &part.mesh);
  part.material = material;
  part.segment = segment;
  part.casts_shadow = casts_shadow;
  scene->parts.push_back(std::move(part));
}

void AddCylinder(SceneGeometry* scene, const std::string& name, const Eigen::Vector3d& bottom_center_m,
                 double radius_m, double height_m, const Material& material) {
  ScenePart part;
  part.name = name;
  part.mesh = MakeCylinderMesh(radius_m, height_m, 24);
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = bottom_center_m + Eigen::Vector3d(0, 0, 0.5 * height_m);
  TransformMesh(at, &part.mesh);
  part.material = material;
  part.casts_shadow = true;
  scene->parts.push_back(std::move(part));
}

void AddBoard(SceneGeometry* scene, const SceneLayout& layout) {
  const Eigen::Vector3d half = 0.5 * layout.board_size_m;
  AddBox(scene, "cutting_board", layout.board_center_m - half, layout.board_center_m + half,
         Make(MaterialKind::kWood, Srgb(200, 160, 112), Srgb(160, 116, 72), 0.06f, 20.0f, 0.007f), true,
         kBoardSegment);
}

void BuildTable(const SceneLayout& layout, SceneGeometry* scene) {
  const Eigen::Vector3d half = 0.5 * layout.table_size_m;
  const Eigen::Vector3d top_min = layout.table_center_m - half, top_max = layout.table_center_m + half;
  const double floor_z = top_min.z() - 0.70;
  AddBox(scene, "table_top", top_min, top_max, Make(MaterialKind::kPlain, Srgb(176, 172, 164), Eigen::Vector3f::Zero(), 0.10f, 30.0f));
  const double leg = 0.06;
  for (int sx = 0; sx < 2; ++sx) {
    for (int sy = 0; sy < 2; ++sy) {
      const double x = sx ? top_max.x() - 0.05 - leg : top_min.x() + 0.05;
      const double y = sy ? top_max.y() - 0.05 - leg : top_min.y() + 0.05;
      AddBox(scene, "table_leg", {x, y, floor_z}, {x + leg, y + leg, top_min.z()},
             Make(MaterialKind::kPlain, Srgb(60, 60, 62), Eigen::Vector3f::Zero(), 0.3f, 40.0f));
    }
  }
  AddBox(scene, "floor", {-3.0, -3.0, floor_z - 0.02}, {4.0, 3.0, floor_z},
         Make(MaterialKind::kPlanks, Srgb(150, 120, 90), Srgb(90, 70, 50), 0.05f, 16.0f, 0.18f));
  // Plain, evenly lit walls at a distance: a neutral studio backdrop.
  const Material wall = Make(MaterialKind::kPlain, Srgb(200, 202, 205), Eigen::Vector3f::Zero(), 0.0f, 8.0f);
  AddBox(scene, "wall_back", {-2.0, -3.0, floor_z}, {-1.95, 3.0, 2.5}, wall);
  AddBox(scene, "wall_left", {-2.0, 2.45, floor_z}, {4.0, 2.5, 2.5}, wall);
  AddBox(scene, "wall_right", {-2.0, -2.5, floor_z}, {4.0, -2.45, 2.5}, wall);
  scene->lighting.direction_to_light = Eigen::Vector3f(0.35f, 0.30f, 0.89f).normalized();
  scene->lighting.light_color = {1.9f, 1.85f, 1.8f};
  scene->lighting.sky_color = {0.42f, 0.44f, 0.48f};
  scene->lighting.ground_color = {0.16f, 0.15f, 0.14f};
  scene->lighting.clear_color = Srgb(200, 202, 205);
}

void BuildKitchen(const SceneLayout& layout, SceneGeometry* scene) {
  const Eigen::Vector3d half = 0.5 * layout.table_size_m;
  const Eigen::Vector3d top_min = layout.table_center_m - half, top_max = layout.table_center_m + half;
  const double floor_z = top_min.z() - 0.86;
  const double wall_x = top_min.x() - 0.02;
  AddBox(scene, "counter_top", top_min, top_max,
         Make(MaterialKind::kStone, Srgb(200, 196, 188), Srgb(120, 116, 110), 0.25f, 60.0f, 0.008f));
  // Base cabinets under the counter, set back a little, with steel handles on the front.
  const Material cabinet = Make(MaterialKind::kPlain, Srgb(120, 140, 125), Eigen::Vector3f::Zero(), 0.15f, 30.0f);
  const Material steel = Make(MaterialKind::kMetal, Srgb(190, 192, 195), Eigen::Vector3f::Zero(), 0.8f, 80.0f);
  AddBox(scene, "base_cabinets", {top_min.x(), top_min.y() + 0.02, floor_z + 0.1},
         {top_max.x() - 0.03, top_max.y() - 0.02, top_min.z()}, cabinet);
  AddBox(scene, "plinth", {top_min.x(), top_min.y() + 0.02, floor_z}, {top_max.x() - 0.08, top_max.y() - 0.02, floor_z + 0.1},
         Make(MaterialKind::kPlain, Srgb(40, 40, 42)));
  const int doors = 4;
  const double door_width = (top_max.y() - top_min.y() - 0.04) / doors;
  for (int d = 0; d < doors; ++d) {
    const double y0 = top_min.y() + 0.02 + d * door_width;
    AddBox(scene, "door_gap", {top_max.x() - 0.031, y0 - 0.003, floor_z + 0.1}, {top_max.x() - 0.029, y0 + 0.003, top_min.z()},
           Make(MaterialKind::kPlain, Srgb(30, 32, 30)));
    AddBox(scene, "door_handle", {top_max.x() - 0.03, y0 + 0.5 * door_width - 0.08, top_min.z() - 0.09},
           {top_max.x() - 0.01, y0 + 0.5 * door_width + 0.08, top_min.z() - 0.075}, steel);
  }
  AddBox(scene, "floor", {-3.0, -3.0, floor_z - 0.02}, {4.0, 3.0, floor_z},
         Make(MaterialKind::kPlanks, Srgb(120, 88, 60), Srgb(70, 50, 35), 0.08f, 20.0f, 0.15f));
  // Back wall: tiled splash-back above the counter, painted above and below.
  const Material paint = Make(MaterialKind::kPlain, Srgb(232, 226, 214), Eigen::Vector3f::Zero(), 0.02f, 8.0f);
  const double side_y = 1.7;
  AddBox(scene, "back_wall_tiles", {wall_x - 0.02, -side_y, top_max.z()}, {wall_x, side_y, top_max.z() + 0.75},
         Make(MaterialKind::kTiles, Srgb(236, 238, 240), Srgb(150, 150, 145), 0.35f, 70.0f, 0.075f));
  AddBox(scene, "back_wall_upper", {wall_x - 0.02, -side_y, top_max.z() + 0.75}, {wall_x, side_y, 2.6}, paint);
  AddBox(scene, "back_wall_lower", {wall_x - 0.02, -side_y, floor_z}, {wall_x, side_y, top_min.z()}, paint);
  // Wall cabinets left and right of the robot, clear of its reach above the base.
  for (int side = -1; side <= 1; side += 2) {
    const double y_near = 0.45, y_far = 1.5;
    const double y0 = side > 0 ? y_near : -y_far, y1 = side > 0 ? y_far : -y_near;
    AddBox(scene, "wall_cabinet", {wall_x, y0, top_max.z() + 0.8}, {wall_x + 0.33, y1, top_max.z() + 1.5}, cabinet);
    AddBox(scene, "wall_cabinet_handle", {wall_x + 0.33, 0.5 * (y0 + y1) - 0.06, top_max.z() + 0.84},
           {wall_x + 0.35, 0.5 * (y0 + y1) + 0.06, top_max.z() + 0.855}, steel);
  }
  // Side walls; the right-hand one (seen by the left camera) has the window the light comes through.
  AddBox(scene, "side_wall_left", {wall_x - 0.02, side_y, floor_z}, {4.0, side_y + 0.02, 2.6}, paint);
  AddBox(scene, "side_wall_right", {wall_x - 0.02, -side_y - 0.02, floor_z}, {4.0, -side_y, 2.6}, paint);
  AddBox(scene, "window", {0.05, -side_y + 0.001, top_max.z() + 0.35}, {1.05, -side_y + 0.01, top_max.z() + 1.25},
         Make(MaterialKind::kEmissive, {1.6f, 1.75f, 1.9f}));
  const Material frame = Make(MaterialKind::kPlain, Srgb(245, 245, 245), Eigen::Vector3f::Zero(), 0.2f, 30.0f);
  AddBox(scene, "window_frame", {0.03, -side_y, top_max.z() + 0.33}, {1.07, -side_y + 0.03, top_max.z() + 0.35}, frame);
  AddBox(scene, "window_frame", {0.03, -side_y, top_max.z() + 1.25}, {1.07, -side_y + 0.03, top_max.z() + 1.27}, frame);
  AddBox(scene, "window_frame", {0.54, -side_y, top_max.z() + 0.35}, {0.56, -side_y + 0.03, top_max.z() + 1.25}, frame);
  // A few jars at the back of the counter, away from the board.
  const Material glass_jar = Make(MaterialKind::kPlain, Srgb(200, 170, 120), Eigen::Vector3f::Zero(), 0.5f, 60.0f);
  const Material lid = Make(MaterialKind::kPlain, Srgb(60, 55, 50), Eigen::Vector3f::Zero(), 0.3f, 40.0f);
  const double jar_y[] = {0.55, 0.68, 0.80};
  const double jar_height[] = {0.16, 0.12, 0.20};
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d base(wall_x + 0.1, jar_y[j], top_max.z());
    AddCylinder(scene, "jar", base, 0.05, jar_height[j], glass_jar);
    AddCylinder(scene, "jar_lid", base + Eigen::Vector3d(0, 0, jar_height[j]), 0.052, 0.02, lid);
  }
  // Daylight from the window side, warm indoor ambient.
  scene->lighting.direction_to_light = Eigen::Vector3f(0.25f, -0.55f, 0.80f).normalized();
  scene->lighting.light_color = {1.8f, 1.75f, 1.65f};
  scene->lighting.sky_color = {0.40f, 0.38f, 0.36f};
  scene->lighting.ground_color = {0.15f, 0.12f, 0.10f};
  scene->lighting.clear_color = Srgb(232, 226, 214);
}

}  // namespace

std::vector<std::string> SceneNames() { return {"table", "kitchen"}; }

SceneGeometry BuildSceneGeometry(const std::string& scene_name, const SceneLayout& layout) {
  SceneGeometry scene;
  scene.scene = scene_name;
  if (scene_name == "table") {
    BuildTable(layout, &scene);
  } else if (scene_name == "kitchen") {
    BuildKitchen(layout, &scene);
  } else {
    throw RenderError("unknown scene '" + scene_name + "'; known scenes: table, kitchen");
  }
  AddBoard(&scene, layout);
  const Eigen::Vector3d work = layout.board_center_m;
  scene.lighting.shadow_center_m = Eigen::Vector3f(0.5f * static_cast<float>(work.x()), static_cast<float>(work.y()), 0.4f);
  scene.lighting.shadow_half_extent_m = 0.9f;
  return scene;
}

}  // namespace culinarycut::render
