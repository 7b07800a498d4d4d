// SceneSpec on the wire <-> the engine's SceneConfig. Reading checks only what the wire can get
// wrong (sizes, non-finite values, counts past an int); the model checks the physical ranges.
#pragma once

#include "culinarycut/v1/simulator.pb.h"
#include "sim/world/food_model.h"
#include "sim/world/scene_config.h"

namespace culinarycut::server {

// Throws FieldError naming the field (e.g. "scene.objects[1].scale", "scene.safety.margin").
SceneConfig SceneFromWire(const v1::SceneSpec& wire);

// The scene with every default filled in, as the client should record it.
v1::SceneSpec SceneToWire(const SceneConfig& config);
// Fills in what the food model resolved: each object's pose and the MPM resolution.
void ResolvedFoodToWire(const FoodModel& food, v1::SceneSpec* wire);
void MpmResolutionToWire(const MpmResolution& resolution, v1::MpmSettings* wire);
// What the accuracy study measured for this resolution (measured = false when it did not run it).
void ExpectedAccuracyToWire(const MpmResolution& resolution, v1::ExpectedAccuracy* wire);
// The engine's quality presets (each with what the study measured for it) and the MPM bounds a scene
// must keep (mass-scaling cap, activity radius in cells): what GetServerInfo and `cc-cut --presets` publish.
void ResolutionCatalogueToWire(v1::ServerInfo* info);

}  // namespace culinarycut::server
