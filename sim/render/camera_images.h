// What one camera produced in one render call. Only the requested channels are filled; the
// others are empty vectors.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/render/camera.h"

namespace culinarycut::render {

struct CameraImages {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;        // H x W x 3, row 0 = top, sRGB
  // H x W, metres along the optical axis (camera z, not the ray length); 0 where no geometry.
  std::vector<float> depth_m;
  std::vector<std::int32_t> segmentation;  // H x W, ids of RenderResult::labels; 0 = background
  CameraIntrinsics intrinsics;
  CameraExtrinsics extrinsics;
};

// What a segmentation id stands for. Ids 0..3 are fixed (background, robot, knife, board); food
// pieces get 4, 5, ... in ascending (object, piece) order, so a food's ids can change when it
// splits: always read them from the labels of the same render call.
struct SegmentLabel {
  std::int32_t id = 0;
  std::string kind;  // "background", "robot", "knife", "board", "food"
  int object = -1;   // food object index, food only
  int piece = -1;    // piece label within the object (ParticleView::piece), food only
  std::string food;  // food name, food only
};

}  // namespace culinarycut::render
