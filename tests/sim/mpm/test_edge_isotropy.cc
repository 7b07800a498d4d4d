// The edge's force must not depend on how the food lies on the grid: the edge's weights across the
// blade (physics/edge_resistance.h) engage the same length of edge at every angle, and a round food
// cut with the blade turned about the vertical meets the same force.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/food_shapes.h"
#include "sim/mpm/physics/edge_resistance.h"

namespace culinarycut::mpm {
namespace {

// The edge length (in dx) the nodes of a square lattice of spacing 1 give per unit of a straight edge
// line at `angle_rad` through (offset, 0): sum of EdgeAcrossWeight(distance) over a long window / its length.
double EngagedLengthPerUnit(double angle_rad, double offset) {
  const double half_window = 200.0;
  const Eigen::Vector2d along(std::cos(angle_rad), std::sin(angle_rad));
  const Eigen::Vector2d across(-along.y(), along.x());
  const Eigen::Vector2d origin(offset, 0.0);
  double sum = 0.0;
  const int reach = static_cast<int>(half_window) + 3;
  for (int i = -reach; i <= reach; ++i) {
    for (int j = -reach; j <= reach; ++j) {
      const Eigen::Vector2d node = Eigen::Vector2d(i, j) - origin;
      const double along_node = node.dot(along);
      if (along_node < -half_window || along_node >= half_window) continue;  // half-open: whole cells
      sum += EdgeAcrossWeight(node.dot(across));
    }
  }
  return sum / (2.0 * half_window);
}

TEST_CASE("the edge's weights across the blade engage the same edge length at every angle to the grid",
          "[mpm][cutting][isotropy]") {
  for (const double degrees : {0.0, 10.0, 22.5, 30.0, 45.0}) {
    for (const double offset : {0.0, 0.17, 0.25, 0.5}) {
      INFO(degrees << " deg, offset " << offset << " cells");
      CHECK(EngagedLengthPerUnit(degrees * M_PI / 180.0, offset) == Approx(1.0).epsilon(0.025));
    }
  }
  // A weight that sums to one per column: exact along a grid line.
  for (const double offset : {0.0, 0.3, 0.5}) CHECK(EngagedLengthPerUnit(0.0, offset) == Approx(1.0).epsilon(1e-9));
}

struct RoundCut {
  double edge_force_n = 0.0;   // mean over the middle of the cut
  double blade_force_n = 0.0;
};

// A soft round food (the orange's shape) on the board, cut through its centre with the blade turned
// `yaw_deg` about the vertical: the same cut of the same particles, only at another angle to the grid.
RoundCut CutRoundFood(double yaw_deg) {
  SolverConfig config;
  config.dx_m = 0.004;
  Solver<float> solver(config, {testing::SoftMaterial(5e4, 0.3)});
  const auto shape = MakeFoodShape("orange", 0.5);
  const Eigen::AlignedBox3d bounds = shape->LocalBounds();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.02 - bounds.min().z());
  SamplingOptions sampling;
  sampling.dx_m = config.dx_m;
  sampling.seed = 3;
  SampleFood(*shape, pose, 1000.0, 0, 0, sampling, &solver.particles());
  testing::AddBoardAndTable(&solver);
  const double top_m = 0.02 + bounds.sizes().z();
  testing::CutScenario scenario;
  scenario.yaw_rad = yaw_deg * M_PI / 180.0;
  scenario.start_height_m = top_m + 0.004;
  scenario.lift_to_m = scenario.start_height_m;
  scenario.settle_s = 0.0;
  const testing::CutResult cut = testing::RunCut(scenario, &solver);
  // The middle of the cut: the edge between 30 % and 70 % of the way down.
  const double low_m = 0.02 + 0.3 * bounds.sizes().z(), high_m = 0.02 + 0.7 * bounds.sizes().z();
  return {testing::MeanForceWhileDescending(cut, cut.edge_force_z_n, low_m, high_m),
          testing::MeanForceWhileDescending(cut, cut.blade_force_z_n, low_m, high_m)};
}

TEST_CASE("a round food cut with the blade turned 22.5 and 45 degrees meets the same force within 5 %",
          "[mpm][cutting][isotropy]") {
  const RoundCut straight = CutRoundFood(0.0);
  REQUIRE(straight.edge_force_n > 0.1);
  for (const double yaw_deg : {22.5, 45.0}) {
    const RoundCut turned = CutRoundFood(yaw_deg);
    INFO("turned " << yaw_deg << " deg: edge " << turned.edge_force_n << " N against " << straight.edge_force_n
                   << " N, blade " << turned.blade_force_n << " N against " << straight.blade_force_n << " N");
    CHECK(turned.edge_force_n == Approx(straight.edge_force_n).epsilon(0.05));
    CHECK(turned.blade_force_n == Approx(straight.blade_force_n).epsilon(0.05));
  }
}

}  // namespace
}  // namespace culinarycut::mpm
