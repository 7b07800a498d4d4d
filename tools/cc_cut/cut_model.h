// A cc-cut file compiled: its scene block read by the server's wire layer and compiled by the
// engine's food model, so the food, its pose and material, the resolution, the colliders and the
// solver come out as a server session would build them; then cc-cut's solver overrides and the
// prescribed knife path on top.
#pragma once

#include "culinarycut/v1/scene.pb.h"
#include "sim/core/scene_layout.h"
#include "sim/world/food_model.h"
#include "sim/world/scene_config.h"
#include "tools/cc_cut/cut_scene.h"
#include "tools/cc_cut/knife_path.h"

namespace culinarycut::cc_cut {

struct CutModel {
  SceneConfig config;   // the scene block as the server reads it
  SceneLayout layout;   // the board and table of every server scene
  FoodModel food;       // one food object; its solver carries cc-cut's overrides
  KnifePath knife;
  double compile_ms = 0.0;  // wall time of the food model's compilation (sampling included)
};

// Throws std::invalid_argument naming the field at fault: a scene the server would refuse, a
// scene with other than one food object or with parts cc-cut does not simulate (robot, cameras,
// task), a solver override out of range, or a cut position outside the food.
CutModel CompileCut(const CutScene& scene);

// The scene block with every default filled in and the food's resolved pose, material and
// resolution, as the server echoes a session's scene (without the robot cc-cut does not have).
v1::SceneSpec ResolvedSceneSpec(const CutModel& model);

}  // namespace culinarycut::cc_cut
