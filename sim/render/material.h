// Surface appearance: a procedural material kind evaluated in the fragment shader, with its
// colours (linear RGB, 0..1) and Blinn-Phong parameters. Patterns are in world coordinates (m).
#pragma once

#include <Eigen/Core>

namespace culinarycut::render {

// The numbers are the shader's material ids (kept in sync with shaders.cc).
enum class MaterialKind : int {
  kPlain = 0,     // colour only
  kWood = 1,      // grain along world x: colour = early wood, second_color = late wood
  kTiles = 2,     // square tiles of pattern_scale_m with grout in second_color, per-tile tint
  kMetal = 3,     // brushed steel: strong highlight and a reflection of sky and ground
  kFood = 4,      // skin (color) blended to flesh (second_color) by the per-vertex flesh weight
  kStone = 5,     // speckled counter top: flecks of second_color
  kPlanks = 6,    // floor planks along world x, pattern_scale_m wide, seams in second_color
  kEmissive = 7,  // a light source seen directly (window): color, unlit
};

struct Material {
  MaterialKind kind = MaterialKind::kPlain;
  Eigen::Vector3f color{0.6f, 0.6f, 0.6f};
  Eigen::Vector3f second_color{0.3f, 0.3f, 0.3f};
  float specular = 0.1f;      // highlight strength
  float shininess = 32.0f;    // Blinn-Phong exponent
  float pattern_scale_m = 0.1f;
};

// Segmentation ids. Food pieces follow from kFirstFoodSegment, one id per (object, piece).
enum SegmentId : int {
  kBackgroundSegment = 0,  // nothing, the table, walls, floor and other furniture
  kRobotSegment = 1,
  kKnifeSegment = 2,
  kBoardSegment = 3,
  kFirstFoodSegment = 4,
};

}  // namespace culinarycut::render
