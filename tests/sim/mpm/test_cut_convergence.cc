// The cutting force answers to the food, not the grid: the edge pushes with the food's toughness
// times the edge length in it (edge_resistance.h) at every dx, and a tougher food takes more work.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"

namespace culinarycut::mpm {
namespace {

using testing::CutResult;
using testing::CutScenario;
using testing::MeanForceWhileDescending;

constexpr double kBlockWidthM = 0.03;  // the block's extent along the blade (world y)

struct BlockCut {
  double edge_force_n = 0.0;   // mean over the middle of the cut
  double blade_force_n = 0.0;  // the same for the whole blade (edge and faces)
  double edge_work_j = 0.0;    // edge force times the depth cut, over the whole descent
  std::size_t pieces = 0;
};

// A 6 x 3 x 3 cm block of soft food on the board, cut through its middle at 0.5 m/s.
BlockCut CutBlock(double dx_m, double toughness_j_m2) {
  SolverConfig config;
  config.dx_m = dx_m;
  Material flesh = testing::SoftMaterial(1e5, 0.3);
  flesh.fracture_toughness_j_m2 = toughness_j_m2;
  Solver<float> solver(config, {flesh});
  testing::AddBlock<float>({0.47, -0.5 * kBlockWidthM, 0.02}, {0.53, 0.5 * kBlockWidthM, 0.05}, dx_m, 2, 1000.0,
                  &solver.particles());
  testing::AddBoardAndTable(&solver);
  CutScenario scenario;
  scenario.cut_x_m = 0.5005;  // between nodes at every dx of the study
  const CutResult cut = testing::RunCut(scenario, &solver);
  BlockCut result;
  // The middle of the cut: the edge between 1 cm and 2.5 cm above the board (top at 5 cm).
  result.edge_force_n = MeanForceWhileDescending(cut, cut.edge_force_z_n, 0.03, 0.045);
  result.blade_force_n = MeanForceWhileDescending(cut, cut.blade_force_z_n, 0.03, 0.045);
  result.edge_work_j = MeanForceWhileDescending(cut, cut.edge_force_z_n, 0.019, 0.05) * 0.031;
  TopologyOptions options;
  options.link_distance_m = 0.75 * dx_m;
  options.min_piece_particles = 20;
  result.pieces = DetectPieces(options, &solver.particles()).size();
  return result;
}

TEST_CASE("the edge's cutting force is toughness times edge length at every dx, converging",
          "[mpm][cutting][convergence]") {
  const double toughness_j_m2 = 100.0;
  const double expected_n = toughness_j_m2 * kBlockWidthM;  // 3 N
  std::vector<BlockCut> cuts;
  for (const double dx_m : {0.006, 0.004, 0.003}) cuts.push_back(CutBlock(dx_m, toughness_j_m2));
  INFO("edge force at dx 6/4/3 mm: " << cuts[0].edge_force_n << " / " << cuts[1].edge_force_n << " / "
                                     << cuts[2].edge_force_n << " N (G_c L = " << expected_n
                                     << " N); blade force " << cuts[0].blade_force_n << " / "
                                     << cuts[1].blade_force_n << " / " << cuts[2].blade_force_n << " N");
  for (const BlockCut& cut : cuts) {
    CHECK(cut.pieces == 2);
    CHECK(cut.edge_force_n == Approx(expected_n).epsilon(0.15));
  }
  // Refinement: the last step changes the edge force by less than the one before, and by < 15 %.
  const double first_change = std::abs(cuts[1].edge_force_n - cuts[0].edge_force_n);
  const double last_change = std::abs(cuts[2].edge_force_n - cuts[1].edge_force_n);
  CHECK(last_change < 0.15 * cuts[2].edge_force_n);
  CHECK(last_change <= first_change + 0.02 * expected_n);
  // The whole blade (edge and faces' friction) converges too, and monotonically.
  const double blade_first = cuts[1].blade_force_n - cuts[0].blade_force_n;
  const double blade_last = cuts[2].blade_force_n - cuts[1].blade_force_n;
  CHECK(std::abs(blade_last) < 0.15 * cuts[2].blade_force_n);
  CHECK(blade_first * blade_last >= 0.0);
  CHECK(std::abs(blade_last) <= std::abs(blade_first));
}

TEST_CASE("a food twice as tough takes about twice the edge work to cut", "[mpm][cutting][convergence]") {
  const BlockCut soft = CutBlock(0.004, 100.0);
  const BlockCut tough = CutBlock(0.004, 200.0);
  INFO("edge work " << soft.edge_work_j << " J vs " << tough.edge_work_j << " J; blade force "
                    << soft.blade_force_n << " N vs " << tough.blade_force_n << " N");
  CHECK(tough.edge_work_j / soft.edge_work_j == Approx(2.0).epsilon(0.15));
  CHECK(tough.blade_force_n > 1.4 * soft.blade_force_n);
  CHECK(soft.pieces == 2);
  CHECK(tough.pieces == 2);
}

}  // namespace
}  // namespace culinarycut::mpm
