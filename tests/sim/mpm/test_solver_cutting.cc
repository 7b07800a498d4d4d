// Knife cuts: fracture into pieces, a clean gap, no leaking through the blade, momentum balance.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {
namespace {

using testing::CutResult;
using testing::CutScenario;

// Pieces bigger than crumbs, and the gap between the two facing the blade plane.
struct PieceReport {
  std::vector<Piece> pieces;
  double gap_m = 0.0;
};

template <typename Real>
PieceReport Pieces(Solver<Real>* solver, double cut_x_m) {
  TopologyOptions options;
  options.link_distance_m = 0.75 * solver->config().dx_m;
  options.min_piece_particles = 20;
  options.separate_blade_sides = false;  // damage alone must separate them
  PieceReport report;
  report.pieces = DetectPieces(options, &solver->particles());
  double left_max = -1.0, right_min = 2.0;
  for (const Piece& piece : report.pieces) {
    if (piece.centroid_m.x() < cut_x_m) left_max = std::max(left_max, piece.bounds_m.max().x());
    if (piece.centroid_m.x() > cut_x_m) right_min = std::min(right_min, piece.bounds_m.min().x());
  }
  report.gap_m = right_min - left_max;
  return report;
}

TEST_CASE("a knife cuts a block into exactly two pieces with a narrow gap", "[mpm][cutting]") {
  SolverConfig config;
  config.dx_m = 0.004;
  const auto block = testing::SoftBlockOnBoard(config);
  Solver<float>& solver = *block;
  const CutResult cut = testing::RunCut(CutScenario{}, &solver);
  const PieceReport report = Pieces(&solver, 0.5);
  INFO("steps " << cut.steps << ", peak blade force " << cut.peak_blade_force_n << " N, gap "
                << report.gap_m * 1e3 << " mm, residual " << cut.worst_momentum_residual
                << ", J in [" << cut.j_min << ", " << cut.j_max << "], max c-hat " << cut.max_c_hat
                << ", broken " << cut.broken_particles << " of " << solver.particles().size());
  CHECK(cut.finite);
  CHECK(report.pieces.size() == 2);
  CHECK(report.gap_m <= 1.5 * config.dx_m);
  CHECK(cut.side_violations == 0);
  CHECK(cut.worst_momentum_residual <= 0.01);
  CHECK(cut.peak_blade_force_n > 0.0);
}

TEST_CASE("a knife cuts a cucumber into exactly two pieces", "[mpm][cutting]") {
  SolverConfig config;
  config.dx_m = 0.004;
  Material flesh = testing::SoftMaterial(5e4, 0.37);  // cucumber's nu, softened E: a fast test
  flesh.density_kg_m3 = 1000.0;
  Solver<float> solver(config, {flesh});
  // A 0.6-scale cucumber (0.12 m long, 0.024 m thick) along world x, lying on the board.
  const auto shape = MakeFoodShape("cucumber", 0.6);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.02 - shape->LocalBounds().min().z());
  SamplingOptions sampling;
  sampling.dx_m = config.dx_m;
  sampling.particles_per_cell = 8;
  SampleFood(*shape, pose, flesh.density_kg_m3, 0, 0, sampling, &solver.particles());
  testing::AddBoardAndTable(&solver);
  CutScenario scenario;
  scenario.cut_x_m = 0.5;
  scenario.start_height_m = 0.02 + shape->LocalBounds().sizes().z() + 0.006;
  scenario.lift_to_m = scenario.start_height_m;
  const CutResult cut = testing::RunCut(scenario, &solver);
  const PieceReport report = Pieces(&solver, 0.5);
  INFO("steps " << cut.steps << ", particles " << solver.particles().size() << ", peak blade force "
                << cut.peak_blade_force_n << " N, gap " << report.gap_m * 1e3 << " mm, residual "
                << cut.worst_momentum_residual);
  CHECK(cut.finite);
  CHECK(report.pieces.size() == 2);
  CHECK(report.gap_m <= 1.5 * config.dx_m);
  CHECK(cut.side_violations == 0);
  CHECK(cut.worst_momentum_residual <= 0.01);
}

TEST_CASE("a 2 mm slice off the end of a block comes off and stays a slice", "[mpm][cutting]") {
  SolverConfig config;
  config.dx_m = 0.002;  // two particle layers across the slice
  Solver<float> solver(config, {testing::SoftMaterial(5e4, 0.3)});
  testing::AddBlock<float>({0.485, -0.01, 0.02}, {0.515, 0.01, 0.04}, config.dx_m, 2, 1000.0, &solver.particles());
  testing::AddBoardAndTable(&solver);
  CutScenario scenario;
  scenario.cut_x_m = 0.513;
  scenario.start_height_m = 0.045;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.1;  // long enough for a slice left touching its block to re-link, were it to
  const CutResult cut = testing::RunCut(scenario, &solver);
  const PieceReport report = Pieces(&solver, scenario.cut_x_m);
  REQUIRE(report.pieces.size() == 2);
  const Piece& slice = report.pieces[0].volume_m3 < report.pieces[1].volume_m3 ? report.pieces[0] : report.pieces[1];
  const double expected_m3 = 0.002 * 0.02 * 0.02;
  INFO("slice " << slice.volume_m3 * 1e6 << " cm^3 (2 mm: " << expected_m3 * 1e6 << "), centroid x "
                << slice.centroid_m.x() << " m, steps " << cut.steps);
  // Particles the edge broke (damage >= 0.9) belong to no piece: the slice keeps a fraction.
  CHECK(slice.volume_m3 > 0.25 * expected_m3);
  CHECK(slice.volume_m3 < 1.5 * expected_m3);
  CHECK(slice.centroid_m.x() > scenario.cut_x_m);
  CHECK(cut.side_violations == 0);
}

TEST_CASE("a knife turned 30 degrees still cuts cleanly and nothing crosses it", "[mpm][cutting]") {
  SolverConfig config;
  config.dx_m = 0.004;
  const auto block = testing::SoftBlockOnBoard(config);
  Solver<float>& solver = *block;
  CutScenario scenario;
  scenario.yaw_rad = M_PI / 6;
  const CutResult cut = testing::RunCut(scenario, &solver);
  INFO("steps " << cut.steps << ", residual " << cut.worst_momentum_residual);
  CHECK(cut.finite);
  CHECK(Pieces(&solver, 0.5).pieces.size() == 2);
  CHECK(cut.side_violations == 0);
  CHECK(cut.worst_momentum_residual <= 0.01);
}

TEST_CASE("a particle with a NaN position stops the step with an error", "[mpm][cutting]") {
  SolverConfig config;
  Solver<float> solver(config, {testing::SoftMaterial()});
  testing::AddBlock<float>({0.48, -0.01, 0.02}, {0.52, 0.01, 0.04}, config.dx_m, 2, 1000.0,
                           &solver.particles());
  solver.particles().position[1][7] = std::nanf("");
  CHECK_THROWS_WITH(solver.Substep(1e-4), Catch::Contains("NaN or Inf position"));
  solver.particles().position[1][7] = 1e30f;
  CHECK_THROWS_WITH(solver.Substep(1e-4), Catch::Contains("too far from the origin"));
}

TEST_CASE("without damage the knife passes through and the block heals", "[mpm][cutting]") {
  SolverConfig config;
  config.dx_m = 0.004;
  config.effects.damage = false;
  const auto block = testing::SoftBlockOnBoard(config);
  Solver<float>& solver = *block;
  const CutResult cut = testing::RunCut(CutScenario{}, &solver);
  CHECK(cut.broken_particles == 0);
  CHECK(cut.side_violations == 0);
  CHECK(Pieces(&solver, 0.5).pieces.size() == 1);
}

}  // namespace
}  // namespace culinarycut::mpm
