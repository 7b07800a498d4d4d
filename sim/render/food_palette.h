// Colours of the paper's seven foods: the skin a whole food shows and the flesh a cut exposes.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace culinarycut::render {

struct FoodColors {
  Eigen::Vector3f skin;   // linear RGB, 0..1
  Eigen::Vector3f flesh;
};

// banana, cucumber, apple, peach, melon, orange, strawberry. Throws RenderError naming the known
// foods for any other name.
const FoodColors& FoodPalette(const std::string& food);
std::vector<std::string> FoodPaletteNames();

}  // namespace culinarycut::render
