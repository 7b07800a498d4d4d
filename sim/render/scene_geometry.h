// The static surroundings of the cut: the cutting board, the table, and either a plain "table"
// scene or a "kitchen" (stone counter, cabinets, tiled back wall, window), each with its light.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/render/material.h"
#include "sim/render/triangle_mesh.h"
#include "sim/core/scene_layout.h"

namespace culinarycut::render {

struct ScenePart {
  std::string name;
  TriangleMesh mesh;  // world frame
  Material material;
  int segment = kBackgroundSegment;
  bool casts_shadow = false;  // only what can shade the work area: keeps the shadow pass cheap
};

struct SceneLighting {
  Eigen::Vector3f direction_to_light{0.3f, 0.4f, 0.87f};  // world, unit: the one shadowed light
  Eigen::Vector3f light_color{2.2f, 2.1f, 2.0f};           // linear radiance scale
  Eigen::Vector3f sky_color{0.35f, 0.38f, 0.42f};          // hemisphere ambient from above
  Eigen::Vector3f ground_color{0.14f, 0.13f, 0.12f};       // and from below
  Eigen::Vector3f clear_color{0.55f, 0.58f, 0.62f};        // linear, where nothing is drawn
  Eigen::Vector3f shadow_center_m{0.4f, 0.0f, 0.3f};       // the shadow map covers a cube here
  float shadow_half_extent_m = 1.0f;
};

struct SceneGeometry {
  std::string scene;
  std::vector<ScenePart> parts;
  SceneLighting lighting;
};

std::vector<std::string> SceneNames();  // "table", "kitchen"

// Throws RenderError naming the known scenes for an unknown name.
SceneGeometry BuildSceneGeometry(const std::string& scene, const SceneLayout& layout);

}  // namespace culinarycut::render
