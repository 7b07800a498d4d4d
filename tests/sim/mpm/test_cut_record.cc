// The cut record: which side of each past cut a particle is on, and pieces that never re-link.
#include <cmath>

#include <catch2/catch.hpp>

#include "sim/mpm/cut_record.h"
#include "sim/mpm/topology.h"

namespace culinarycut::mpm {
namespace {

TEST_CASE("cut records: bits per cut, and who is on the same side of every cut", "[mpm][topology]") {
  const std::uint32_t left = RecordCut(0u, 0, false);
  const std::uint32_t right = RecordCut(0u, 0, true);
  CHECK(left == 0b01u);
  CHECK(right == 0b11u);
  CHECK_FALSE(SameSideOfEveryCut(left, right));
  CHECK(SameSideOfEveryCut(left, left));
  CHECK(SameSideOfEveryCut(0u, right));  // a particle the edge never passed parts from no one
  // Two cuts: the same side of the first, opposite sides of the second.
  const std::uint32_t a = RecordCut(right, 1, false);
  const std::uint32_t b = RecordCut(right, 1, true);
  CHECK(a == 0b0111u);
  CHECK_FALSE(SameSideOfEveryCut(a, b));
  CHECK(SameSideOfEveryCut(a, RecordCut(0u, 1, false)));
  // Passing again in the same cut keeps the last side only.
  CHECK(RecordCut(right, 0, false) == left);
  CHECK(ValidCutRecord(a));
  CHECK_FALSE(ValidCutRecord(0b10u));  // a side without having been passed
  CHECK(RecordCut(0u, kMaxRecordedCuts - 1, true) == 0xC0000000u);
}

TEST_CASE("a cut's blade normal is the time-weighted principal axis of the blade's normals", "[mpm]") {
  BladeNormalMoment moment;
  CHECK_FALSE(moment.MeanNormal().has_value());  // the edge never passed food
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  moment.Add(y, 0.3);
  moment.Add(-y, 0.1);  // the same plane with its normal flipped counts the same
  const Eigen::Vector3d tilted(0.0, std::cos(0.2), std::sin(0.2));
  moment.Add(2.0 * tilted, 1e-6);  // normalised, and a short time weighs little
  REQUIRE(moment.MeanNormal().has_value());
  CHECK(std::abs(moment.MeanNormal()->dot(y)) == Approx(1.0).margin(1e-6));
  CHECK(moment.duration_s == Approx(0.4 + 1e-6));
  CHECK(moment.normal_outer_s.trace() == Approx(moment.duration_s));
  // Two tilts held equally long: the mean lies halfway between them.
  BladeNormalMoment rocking;
  rocking.Add(Eigen::Vector3d(0.0, std::cos(0.1), std::sin(0.1)), 0.5);
  rocking.Add(Eigen::Vector3d(0.0, std::cos(-0.1), std::sin(-0.1)), 0.5);
  CHECK(std::abs(rocking.MeanNormal()->dot(y)) == Approx(1.0).margin(1e-12));
}

TEST_CASE("particles a cut put on opposite sides never link, however close", "[mpm][topology]") {
  Particles<float> particles;
  // Two rows of particles 0.5 mm apart across x = 0 (well within the link distance).
  for (int i = 0; i < 10; ++i) {
    particles.Add({-0.00025f, 0.001f * i, 0.0f}, 1e-3f, 1e-9f, 0, 0);
    particles.Add({0.00025f, 0.001f * i, 0.0f}, 1e-3f, 1e-9f, 0, 0);
  }
  TopologyOptions options;
  options.link_distance_m = 0.003;
  CHECK(DetectPieces(options, &particles).size() == 1);
  for (std::size_t q = 0; q < particles.size(); ++q) {
    particles.cut_sides[q] = RecordCut(0u, 0, particles.position[0][q] > 0.0f);
  }
  CHECK(DetectPieces(options, &particles).size() == 2);
  options.separate_cut_sides = false;
  CHECK(DetectPieces(options, &particles).size() == 1);
}

}  // namespace
}  // namespace culinarycut::mpm
