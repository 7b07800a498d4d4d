// The plane a cut went along, measured from the food it parted: the material the blade labelled on
// each side of it (positive and negative). The plane is Fisher's linear discriminant between the two
// sides (Fisher, "The use of multiple measurements in taxonomic problems", 1936): the direction that
// separates them best against their spread, refined on the material nearest the fitted plane.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace culinarycut::task {

struct FittedPlane {
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  // on the plane, between the two sides' centres
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // unit, pointing to the positive side
};

// Fewer points than this on either side give no plane.
constexpr std::size_t kMinPointsPerSide = 8;

// The plane between the `positive` and `negative` points (m), or nullopt when either side has
// fewer than kMinPointsPerSide points or the sides do not separate (their centres coincide).
std::optional<FittedPlane> FitCutPlane(const std::vector<Eigen::Vector3d>& positive,
                                       const std::vector<Eigen::Vector3d>& negative);

}  // namespace culinarycut::task
