// The reference specimens of DiSECt's published LS-DYNA cutting runs (Heiden et al., RSS 2021,
// dataset README): a rectangular prism and a half-cylinder lying on its flat face, each pressed by a
// vertical knife. They are not foods (no produce has these shapes); cc-cut cuts them with a food's
// material to compare the engine's force with those references (docs/physics_validation.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {

// `kind` "box": size_m = (length along local x, width along y, height z). "half_cylinder": its axis
// along local x, flat face down; size_m = (length, 2 * radius, radius). Throws std::invalid_argument
// for an unknown kind or a size that is not finite and positive (a half-cylinder's width must be
// twice its height).
std::unique_ptr<FoodShape> MakeSpecimenShape(const std::string& kind, const Eigen::Vector3d& size_m);
std::vector<std::string> SpecimenShapeNames();

}  // namespace culinarycut::mpm
