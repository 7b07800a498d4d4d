// A cc-cut file as plain data: the server's SceneSpec (the food, its pose and material, the MPM
// resolution and effects, the seed) and what SceneSpec does not carry: the knife's prescribed path
// and overrides of the solver's numbers. Schema and units: tools/cc_cut/README.md.
#pragma once

#include <optional>
#include <string>

#include "culinarycut/v1/scene.pb.h"
#include "sim/world/scene_config.h"
#include "tools/cc_cut/knife_path.h"
#include "tools/cc_cut/solver_overrides.h"

namespace culinarycut::cc_cut {

struct CutScene {
  std::string description;  // free text, not used
  v1::SceneSpec scene;      // as the server reads it; cc-cut needs exactly one food object
  SolverOverrides solver;
  KnifePath knife;
  std::optional<SpecimenConfig> specimen;  // cut a reference specimen of the food's material instead
};

// Parses a file's text; absent fields keep their defaults. Throws std::invalid_argument whose
// message names the field ("knife.descent_speed_m_s: must be in (0, 20], got -1",
// "scene.objects[0].scale: expected a number, got a string"): unknown key, wrong type, out of
// range. What needs the compiled food (a bad food or material name, a cut outside the food) is
// checked by CompileCut (cut_model.h).
CutScene CutSceneFromJson(const std::string& json_text);

// The scene as JSON: `scene` in protobuf JSON form with every scalar written (zeros keep their
// SceneSpec meaning), the solver overrides that are set, every knife field (an unset cut position
// is written as cut_fraction 0.5). CutSceneFromJson reads it back to an equal scene.
std::string CutSceneToJson(const CutScene& scene);

}  // namespace culinarycut::cc_cut
