#include "sim/task/cut_plane_fit.h"

#include <cmath>
#include <functional>
#include <utility>
#include <random>

#include <catch2/catch.hpp>
#include <Eigen/Geometry>

namespace culinarycut::task {
namespace {

double DegreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// What the blade labels in a cut: a jittered lattice (`spacing_m`, like particles) inside `inside`,
// within `half_width_m` of the plane (point, normal), split by the side each point is on.
void LabelSlab(const std::function<bool(const Eigen::Vector3d&)>& inside, double spacing_m,
               const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double half_width_m,
               std::vector<Eigen::Vector3d>* positive, std::vector<Eigen::Vector3d>* negative) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.25 * spacing_m, 0.25 * spacing_m);
  const double reach_m = 0.12;
  for (double x = -reach_m; x <= reach_m; x += spacing_m) {
    for (double y = -reach_m; y <= reach_m; y += spacing_m) {
      for (double z = -reach_m; z <= reach_m; z += spacing_m) {
        const Eigen::Vector3d at(x + jitter(random), y + jitter(random), z + jitter(random));
        if (!inside(at)) continue;
        const double side_m = (at - point).dot(normal);
        if (std::abs(side_m) >= half_width_m) continue;
        (side_m >= 0.0 ? positive : negative)->push_back(at);
      }
    }
  }
}

// A cut tilted by `tilt_deg` from vertical about the y axis through `point`.
Eigen::Vector3d TiltedNormal(double tilt_deg) {
  return Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitX();
}

TEST_CASE("a cut's plane is recovered from the material either side of it", "[task][cut_plane]") {
  // Draft-resolution particles (4 mm apart) and the draft split width (about 17 mm each side).
  const double spacing_m = 0.004, half_width_m = 0.017;
  using Shape = std::function<bool(const Eigen::Vector3d&)>;
  const std::pair<const char*, Shape> shapes[] = {
      {"apple", [](const Eigen::Vector3d& x) { return x.norm() < 0.04; }},
      {"cucumber", [](const Eigen::Vector3d& x) {  // lying along x, 40 mm across
         return std::abs(x.x()) < 0.1 && std::hypot(x.y(), x.z()) < 0.02;
       }}};
  for (double tilt_deg : {0.0, 20.0, 35.0}) {
    for (const auto& [name, inside] : shapes) {
      const Eigen::Vector3d point(0.01, 0.0, 0.005);
      const Eigen::Vector3d normal = TiltedNormal(tilt_deg);
      std::vector<Eigen::Vector3d> positive, negative;
      LabelSlab(inside, spacing_m, point, normal, half_width_m, &positive, &negative);
      const std::optional<FittedPlane> plane = FitCutPlane(positive, negative);
      REQUIRE(plane.has_value());
      INFO("tilt " << tilt_deg << " deg, " << name);
      // Well inside the 9 deg the success rule allows (what is left is the lattice's own roughness).
      CHECK(DegreesBetween(plane->normal, normal) < 2.0);
      CHECK(std::abs((plane->point_m - point).dot(normal)) < 0.5 * spacing_m);
    }
  }
}

TEST_CASE("a cut plane needs material on both sides", "[task][cut_plane]") {
  std::vector<Eigen::Vector3d> positive(20, Eigen::Vector3d(0.01, 0, 0)), negative(3, Eigen::Vector3d::Zero());
  CHECK_FALSE(FitCutPlane(positive, negative).has_value());
  negative.assign(20, Eigen::Vector3d(0.01, 0, 0));  // both sides at one place: no direction
  CHECK_FALSE(FitCutPlane(positive, negative).has_value());
}

}  // namespace
}  // namespace culinarycut::task
