// Hard cuts come out right, not only finite: a knife faster than sound, nearly incompressible
// flesh, a stiff food and a long saw each cut a block into two pieces where the blade went.
#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"

namespace culinarycut::mpm {
namespace {

using testing::CutResult;
using testing::CutScenario;

std::vector<Piece> Pieces(Solver<float>* solver) {
  TopologyOptions options;
  options.link_distance_m = 0.75 * solver->config().dx_m;
  options.min_piece_particles = 20;
  return DetectPieces(options, &solver->particles());
}

// Two pieces, one on each side of the blade plane x = 0.5 m, with about half the block each.
void CheckCutInTwo(Solver<float>* solver, const CutResult& cut) {
  const std::vector<Piece> pieces = Pieces(solver);
  INFO("pieces " << pieces.size() << ", steps " << cut.steps << ", speed caps " << cut.speed_caps
                 << ", J in [" << cut.j_min << ", " << cut.j_max << "], peak blade force "
                 << cut.peak_blade_force_n << " N");
  CHECK(cut.finite);
  REQUIRE(pieces.size() == 2);
  CHECK((pieces[0].centroid_m.x() - 0.5) * (pieces[1].centroid_m.x() - 0.5) < 0.0);
  CHECK(pieces[0].volume_m3 == Approx(pieces[1].volume_m3).epsilon(0.3));
  CHECK(cut.side_violations == 0);
}

TEST_CASE("a knife at 10 m/s, faster than the food's sound speed, cuts it in two", "[mpm][hard]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.3));  // c = 8.3 m/s
  const Eigen::Vector3d before = testing::CentreOfMass(solver.particles());
  CutScenario scenario;
  scenario.start_height_m = 0.045;
  scenario.speed_m_s = 10.0;
  scenario.lift_speed_m_s = 1.0;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.01;
  const CutResult cut = testing::RunCut(scenario, &solver);
  CheckCutInTwo(&solver, cut);
  CHECK(cut.speed_caps == 0);
  // Cut, not launched: the food's centre of mass stays within a few mm.
  CHECK((testing::CentreOfMass(solver.particles()) - before).norm() < 0.004);
}

TEST_CASE("nearly incompressible flesh (nu = 0.499) is cut in two", "[mpm][hard]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.499));
  CutScenario scenario;
  scenario.start_height_m = 0.045;
  scenario.speed_m_s = 1.0;
  scenario.lift_to_m = 0.045;
  scenario.settle_s = 0.005;
  CheckCutInTwo(&solver, testing::RunCut(scenario, &solver));
}

TEST_CASE("a stiff food (E = 50 MPa) is cut in two with no particle at the speed cap", "[mpm][hard]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(50e6, 0.3));
  CutScenario scenario;
  scenario.start_height_m = 0.042;
  scenario.speed_m_s = 2.0;
  scenario.lift_speed_m_s = 2.0;
  scenario.lift_to_m = 0.042;
  scenario.settle_s = 0.0005;
  const CutResult cut = testing::RunCut(scenario, &solver);
  CheckCutInTwo(&solver, cut);
  CHECK(cut.speed_caps == 0);
}

TEST_CASE("3 s of sawing keeps the food in place within a few mm and cuts it", "[mpm][hard]") {
  Solver<float> solver = testing::SmallBlockOnBoard(testing::SoftMaterial(5e4, 0.3));
  const Eigen::Vector3d before = testing::CentreOfMass(solver.particles());
  CutScenario scenario;
  scenario.start_height_m = 0.041;
  scenario.speed_m_s = 0.0075;          // 2.25 cm in 3 s ...
  scenario.saw_frequency_hz = 2.0;      // ... with 6 strokes of +-5 mm along the blade
  scenario.saw_amplitude_m = 0.005;
  scenario.lift_to_m = 0.041;
  scenario.settle_s = 0.005;
  const CutResult cut = testing::RunCut(scenario, &solver);
  const Eigen::Vector3d moved = testing::CentreOfMass(solver.particles()) - before;
  INFO("centre of mass moved " << moved.transpose() * 1e3 << " mm");
  CheckCutInTwo(&solver, cut);
  CHECK(std::abs(moved.y()) < 0.003);  // along the strokes
  CHECK(moved.head<2>().norm() < 0.004);
}

}  // namespace
}  // namespace culinarycut::mpm
