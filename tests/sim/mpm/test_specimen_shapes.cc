// The LS-DYNA reference specimens: a box and a half-cylinder lying on its flat face, negative inside,
// positive outside, with tight bounds.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "sim/mpm/specimen_shapes.h"

namespace culinarycut::mpm {
namespace {

TEST_CASE("a box specimen is its size", "[mpm][specimen]") {
  const auto box = MakeSpecimenShape("box", Eigen::Vector3d(0.1, 0.1, 0.05));
  CHECK(box->LocalBounds().sizes().isApprox(Eigen::Vector3d(0.1, 0.1, 0.05)));
  CHECK(box->SignedDistance(Eigen::Vector3d::Zero()) == Approx(-0.025));
  CHECK(box->SignedDistance(Eigen::Vector3d(0.0, 0.0, 0.03)) == Approx(0.005));
  CHECK(box->SignedDistance(Eigen::Vector3d(0.049, 0.049, 0.024)) < 0.0);
}

TEST_CASE("a half-cylinder specimen lies on its flat face, round side up", "[mpm][specimen]") {
  const double radius = 0.05;
  const auto half = MakeSpecimenShape("half_cylinder", Eigen::Vector3d(0.1, 2 * radius, radius));
  CHECK(half->LocalBounds().sizes().isApprox(Eigen::Vector3d(0.1, 0.1, 0.05)));
  const double bottom = -0.5 * radius;
  // Full width on the flat face, a point at the top of the arc, nothing below the face.
  CHECK(half->SignedDistance(Eigen::Vector3d(0.0, 0.049, bottom + 0.0005)) < 0.0);
  CHECK(half->SignedDistance(Eigen::Vector3d(0.0, 0.0, bottom + radius - 0.0005)) < 0.0);
  CHECK(half->SignedDistance(Eigen::Vector3d(0.0, 0.03, bottom + 0.045)) > 0.0);  // outside the arc
  CHECK(half->SignedDistance(Eigen::Vector3d(0.0, 0.0, bottom - 0.001)) > 0.0);
  CHECK(half->SignedDistance(Eigen::Vector3d(0.051, 0.0, 0.0)) > 0.0);
}

TEST_CASE("unknown specimens and bad sizes are refused", "[mpm][specimen]") {
  CHECK_THROWS_AS(MakeSpecimenShape("cone", Eigen::Vector3d(0.1, 0.1, 0.1)), std::invalid_argument);
  CHECK_THROWS_AS(MakeSpecimenShape("box", Eigen::Vector3d(0.1, -0.1, 0.1)), std::invalid_argument);
  CHECK_THROWS_AS(MakeSpecimenShape("half_cylinder", Eigen::Vector3d(0.1, 0.1, 0.1)), std::invalid_argument);
}

}  // namespace
}  // namespace culinarycut::mpm
