#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <vector>

#include "sim/mpm/topology.h"

namespace culinarycut::mpm {
namespace {

constexpr double kSpacingM = 0.002;
constexpr double kParticleMassKg = 1e-3;
constexpr double kParticleVolumeM3 = kSpacingM * kSpacingM * kSpacingM;

// 1.5 lattice spacings: face neighbours link, a missing or broken column breaks the link.
TopologyOptions LatticeOptions() {
  TopologyOptions options;
  options.link_distance_m = 1.5 * kSpacingM;
  return options;
}

// Adds an nx x ny x nz lattice block starting at `origin_m`; `keep(i, j, k)` can leave sites out.
template <typename Real>
void AddBlock(Particles<Real>* particles, const std::array<double, 3>& origin_m, int nx, int ny,
              int nz, std::uint16_t object = 0,
              const std::function<bool(int, int, int)>& keep = nullptr) {
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        if (keep && !keep(i, j, k)) continue;
        particles->Add({static_cast<Real>(origin_m[0] + i * kSpacingM),
                        static_cast<Real>(origin_m[1] + j * kSpacingM),
                        static_cast<Real>(origin_m[2] + k * kSpacingM)},
                       static_cast<Real>(kParticleMassKg), static_cast<Real>(kParticleVolumeM3), 0,
                       object);
      }
    }
  }
}

std::size_t CountLabel(const Particles<double>& particles, std::int32_t label) {
  return static_cast<std::size_t>(
      std::count(particles.piece.begin(), particles.piece.end(), label));
}

TEST_CASE("one block is one piece with its count, volume, bounds and centroid", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.1, -0.05, 0.2}, 10, 6, 4);
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 1);
  const Piece& piece = pieces[0];
  CHECK(piece.label == 0);
  CHECK(piece.object == 0);
  CHECK(piece.particle_count == 240);
  CHECK(piece.volume_m3 == Approx(240 * kParticleVolumeM3));
  CHECK(piece.mass_kg == Approx(240 * kParticleMassKg));
  CHECK(piece.bounds_m.min().isApprox(Eigen::Vector3d(0.1, -0.05, 0.2), 1e-12));
  CHECK(piece.bounds_m.max().isApprox(
      Eigen::Vector3d(0.1 + 9 * kSpacingM, -0.05 + 5 * kSpacingM, 0.2 + 3 * kSpacingM), 1e-12));
  CHECK(piece.centroid_m.isApprox(piece.bounds_m.center(), 1e-12));
  CHECK(CountLabel(particles, 0) == 240);
}

TEST_CASE("the centroid is mass-weighted", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 2, 1, 1);
  particles.mass[1] = 3 * kParticleMassKg;
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 1);
  CHECK(pieces[0].centroid_m.x() == Approx(0.75 * kSpacingM));
  CHECK(pieces[0].mass_kg == Approx(4 * kParticleMassKg));
}

TEST_CASE("a gap splits a block into two pieces", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 20, 5, 5, 0,
           [](int i, int, int) { return i < 8 || i > 9; });
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].particle_count == 8 * 25);
  CHECK(pieces[1].particle_count == 10 * 25);
  CHECK(pieces[0].bounds_m.max().x() == Approx(7 * kSpacingM));
  CHECK(pieces[1].bounds_m.min().x() == Approx(10 * kSpacingM));
}

TEST_CASE("a band of broken particles splits a block; a damaged band does not", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 20, 5, 5);
  auto set_band_damage = [&](double damage) {
    for (std::size_t p = 0; p < particles.size(); ++p) {
      if (std::abs(particles.position[0][p] - 10 * kSpacingM) < 0.5 * kSpacingM) {
        particles.damage[p] = damage;
      }
    }
  };

  set_band_damage(1.0);
  std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].particle_count == 10 * 25);
  CHECK(pieces[1].particle_count == 9 * 25);
  CHECK(CountLabel(particles, -1) == 25);  // broken particles belong to no piece
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (particles.damage[p] >= 1.0) CHECK(particles.piece[p] == -1);
  }

  set_band_damage(0.5);
  pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 1);
  CHECK(pieces[0].particle_count == 20 * 25);
}

TEST_CASE("opposite blade sides do not link; unassigned links with either side",
          "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 12, 4, 4);
  auto assign = [&](double plane_x_m) {
    for (std::size_t p = 0; p < particles.size(); ++p) {
      particles.blade_side[p] = static_cast<std::int8_t>(
          particles.position[0][p] < plane_x_m ? BladeSide::kNegative : BladeSide::kPositive);
    }
  };

  assign(5.5 * kSpacingM);
  TopologyOptions options = LatticeOptions();
  std::vector<Piece> pieces = DetectPieces(options, &particles);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].particle_count == 6 * 16);
  CHECK(pieces[1].particle_count == 6 * 16);

  options.separate_blade_sides = false;
  CHECK(DetectPieces(options, &particles).size() == 1);
  options.separate_blade_sides = true;

  // An unassigned column between the two sides bridges them.
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (std::abs(particles.position[0][p] - 6 * kSpacingM) < 0.5 * kSpacingM) {
      particles.blade_side[p] = static_cast<std::int8_t>(BladeSide::kUnassigned);
    }
  }
  CHECK(DetectPieces(options, &particles).size() == 1);

  std::fill(particles.blade_side.begin(), particles.blade_side.end(),
            static_cast<std::int8_t>(BladeSide::kUnassigned));
  CHECK(DetectPieces(options, &particles).size() == 1);
}

TEST_CASE("two touching objects are two pieces", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 5, 5, 5, 3);
  AddBlock(&particles, {5 * kSpacingM, 0.0, 0.0}, 5, 5, 5, 7);
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].object == 3);
  CHECK(pieces[1].object == 7);
  CHECK(pieces[0].particle_count == 125);
  CHECK(pieces[1].particle_count == 125);
}

TEST_CASE("components under min_piece_particles are crumbs labelled -1", "[mpm][topology]") {
  Particles<double> particles;
  particles.Add({0.5, 0.5, 0.5}, kParticleMassKg, kParticleVolumeM3, 0, 0);  // lone crumb first
  AddBlock(&particles, {0.0, 0.0, 0.0}, 6, 6, 6);
  AddBlock(&particles, {0.1, 0.0, 0.0}, 2, 2, 1);  // a four-particle crumb
  TopologyOptions options = LatticeOptions();
  options.min_piece_particles = 5;
  std::vector<Piece> pieces = DetectPieces(options, &particles);
  REQUIRE(pieces.size() == 1);
  CHECK(pieces[0].label == 0);
  CHECK(pieces[0].particle_count == 216);
  CHECK(particles.piece[0] == -1);
  CHECK(particles.piece[1] == 0);
  CHECK(CountLabel(particles, -1) == 5);

  options.min_piece_particles = 1;
  pieces = DetectPieces(options, &particles);
  REQUIRE(pieces.size() == 3);
  CHECK(pieces[0].particle_count == 1);
  CHECK(pieces[1].particle_count == 216);
  CHECK(pieces[2].particle_count == 4);
}

TEST_CASE("labels follow the lowest particle index and repeat exactly", "[mpm][topology]") {
  // Two interleaved rows: even indices in one row, odd in the other, far apart in y.
  Particles<double> particles;
  for (int i = 0; i < 50; ++i) {
    particles.Add({i * kSpacingM, 0.0, 0.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
    particles.Add({(49 - i) * kSpacingM, 0.05, 0.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  }
  const std::vector<Piece> first = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(first.size() == 2);
  for (std::size_t p = 0; p < particles.size(); ++p) CHECK(particles.piece[p] == int(p % 2));
  const std::vector<std::int32_t> labels = particles.piece;
  for (int run = 0; run < 3; ++run) {
    const std::vector<Piece> again = DetectPieces(LatticeOptions(), &particles);
    CHECK(particles.piece == labels);
    REQUIRE(again.size() == first.size());
    for (std::size_t k = 0; k < again.size(); ++k) {
      CHECK(again[k].particle_count == first[k].particle_count);
      CHECK(again[k].centroid_m == first[k].centroid_m);
      CHECK(again[k].volume_m3 == first[k].volume_m3);
    }
  }
}

TEST_CASE("shuffling the particles gives the same partition", "[mpm][topology]") {
  Particles<double> ordered;
  AddBlock(&ordered, {0.0, 0.0, 0.0}, 30, 6, 6, 0,
           [](int i, int j, int) { return i % 10 != 4 && !(i > 20 && j == 3); });
  AddBlock(&ordered, {0.0, 0.0, 0.02}, 8, 8, 3, 1);
  ordered.damage[17] = 1.0;
  // Four segments along x, the last split in two by the missing row, and the second object.
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &ordered);
  REQUIRE(pieces.size() == 6);

  std::vector<std::size_t> permutation(ordered.size());
  std::iota(permutation.begin(), permutation.end(), 0);
  std::mt19937 rng(12345);
  std::shuffle(permutation.begin(), permutation.end(), rng);
  Particles<double> shuffled;
  for (std::size_t p : permutation) {
    shuffled.Add({ordered.position[0][p], ordered.position[1][p], ordered.position[2][p]},
                 ordered.mass[p], ordered.volume[p], 0, ordered.object[p]);
    shuffled.damage.back() = ordered.damage[p];
  }
  const std::vector<Piece> shuffled_pieces = DetectPieces(LatticeOptions(), &shuffled);
  REQUIRE(shuffled_pieces.size() == pieces.size());

  // The labels may differ, but they must map one-to-one (same sets of particles).
  std::map<std::int32_t, std::int32_t> forward, backward;
  for (std::size_t q = 0; q < permutation.size(); ++q) {
    const std::int32_t a = ordered.piece[permutation[q]];
    const std::int32_t b = shuffled.piece[q];
    CHECK((a == -1) == (b == -1));
    if (a == -1) continue;
    CHECK(forward.emplace(a, b).first->second == b);
    CHECK(backward.emplace(b, a).first->second == a);
  }
  for (const auto& [a, b] : forward) {
    CHECK(pieces[a].particle_count == shuffled_pieces[b].particle_count);
    CHECK(pieces[a].centroid_m.isApprox(shuffled_pieces[b].centroid_m, 1e-12));
  }
}

// The reference: all pairs, the same link rule, components by flood fill from the lowest index.
std::vector<std::int32_t> BruteForceLabels(const Particles<double>& particles,
                                           const TopologyOptions& options) {
  const std::size_t n = particles.size();
  auto active = [&](std::size_t p) { return particles.damage[p] < options.broken_damage; };
  auto linked = [&](std::size_t a, std::size_t b) {
    double d2 = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double d = particles.position[axis][a] - particles.position[axis][b];
      d2 += d * d;
    }
    return d2 < options.link_distance_m * options.link_distance_m &&
           particles.object[a] == particles.object[b] &&
           (!options.separate_blade_sides ||
            particles.blade_side[a] * particles.blade_side[b] >= 0);
  };
  std::vector<std::int32_t> labels(n, -1);
  std::vector<bool> seen(n, false);
  std::int32_t next = 0;
  for (std::size_t start = 0; start < n; ++start) {
    if (seen[start] || !active(start)) continue;
    std::vector<std::size_t> component{start}, stack{start};
    seen[start] = true;
    while (!stack.empty()) {
      const std::size_t a = stack.back();
      stack.pop_back();
      for (std::size_t b = 0; b < n; ++b) {
        if (seen[b] || !active(b) || !linked(a, b)) continue;
        seen[b] = true;
        stack.push_back(b);
        component.push_back(b);
      }
    }
    if (static_cast<int>(component.size()) < options.min_piece_particles) continue;
    for (std::size_t p : component) labels[p] = next;
    ++next;
  }
  return labels;
}

TEST_CASE("random scenes match an all-pairs reference", "[mpm][topology]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int scene = 0; scene < 20; ++scene) {
    Particles<double> particles;
    const int count = 300 + scene * 40;
    const double size_m = 0.02 + 0.002 * scene;  // from dense to sparse
    for (int q = 0; q < count; ++q) {
      particles.Add({size_m * unit(rng), size_m * unit(rng), 0.5 * size_m * unit(rng)},
                    kParticleMassKg, kParticleVolumeM3, 0, static_cast<std::uint16_t>(q % 7 == 0));
      particles.damage.back() = unit(rng) < 0.1 ? 1.0 : 0.3;
      const double side = unit(rng);
      particles.blade_side.back() = static_cast<std::int8_t>(
          side < 0.15 ? BladeSide::kNegative
                      : (side < 0.3 ? BladeSide::kPositive : BladeSide::kUnassigned));
    }
    TopologyOptions options = LatticeOptions();
    options.min_piece_particles = 1 + scene % 3;
    options.separate_blade_sides = scene % 4 != 1;
    INFO("scene " << scene);
    const std::vector<Piece> pieces = DetectPieces(options, &particles);
    const std::vector<std::int32_t> expected = BruteForceLabels(particles, options);
    CHECK(particles.piece == expected);
    CHECK(pieces.size() ==
          static_cast<std::size_t>(*std::max_element(expected.begin(), expected.end()) + 1));
  }
}

TEST_CASE("far-flung particles take the sparse grid and give the same pieces", "[mpm][topology]") {
  Particles<double> particles;
  AddBlock(&particles, {0.0, 0.0, 0.0}, 10, 10, 10, 0, [](int i, int, int) { return i != 5; });
  particles.Add({1000.0, -2000.0, 3000.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  particles.Add({1000.0 + kSpacingM, -2000.0, 3000.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  particles.Add({1e30, 0.0, 0.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  particles.Add({std::nan(""), 0.0, 0.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 4);
  CHECK(pieces[0].particle_count == 500);
  CHECK(pieces[1].particle_count == 400);
  CHECK(pieces[2].particle_count == 2);
  CHECK(pieces[3].particle_count == 1);
  CHECK(particles.piece.back() == -1);  // a non-finite position belongs to no piece
}

TEST_CASE("no particles, no pieces; a bad link distance is refused", "[mpm][topology]") {
  Particles<double> particles;
  CHECK(DetectPieces(LatticeOptions(), &particles).empty());
  particles.Add({0.0, 0.0, 0.0}, kParticleMassKg, kParticleVolumeM3, 0, 0);
  TopologyOptions options;
  options.link_distance_m = 0.0;
  CHECK_THROWS_WITH(DetectPieces(options, &particles), Catch::Contains("link_distance_m"));
}

TEST_CASE("cut positions lie midway between neighbouring pieces along the axis",
          "[mpm][topology]") {
  Particles<double> particles;
  // Three pieces along x: [0, 18] mm, [24, 42] mm, [50, 68] mm (spacing 2 mm); added out of order.
  AddBlock(&particles, {0.050, 0.0, 0.0}, 10, 4, 4);
  AddBlock(&particles, {0.0, 0.0, 0.0}, 10, 4, 4);
  AddBlock(&particles, {0.024, 0.0, 0.0}, 10, 4, 4);
  AddBlock(&particles, {0.030, 0.05, 0.0}, 3, 3, 3, 1);  // another object: ignored
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 4);

  const Eigen::Vector3d origin(-0.01, 0.3, -0.2);
  std::vector<double> cuts = CutPositionsAlongAxis(pieces, 0, origin, Eigen::Vector3d::UnitX());
  REQUIRE(cuts.size() == 2);
  CHECK(cuts[0] == Approx(0.021 + 0.01));
  CHECK(cuts[1] == Approx(0.046 + 0.01));

  // Reversed axis: positions measured the other way, still in ascending order.
  cuts =
      CutPositionsAlongAxis(pieces, 0, Eigen::Vector3d(0.1, 0.0, 0.0), -Eigen::Vector3d::UnitX());
  REQUIRE(cuts.size() == 2);
  CHECK(cuts[0] == Approx(0.1 - 0.046));
  CHECK(cuts[1] == Approx(0.1 - 0.021));

  CHECK(CutPositionsAlongAxis(pieces, 1, origin, Eigen::Vector3d::UnitX()).empty());
  CHECK(CutPositionsAlongAxis(pieces, 2, origin, Eigen::Vector3d::UnitX()).empty());
}

TEST_CASE("cut positions are where the pieces' material came from, however far they slid", "[mpm][topology]") {
  Particles<double> particles;
  // Two pieces cut apart at x = 21 mm ([0, 18] mm and [24, 42] mm as sampled) ...
  AddBlock(&particles, {0.0, 0.0, 0.0}, 10, 4, 4);
  AddBlock(&particles, {0.024, 0.0, 0.0}, 10, 4, 4);
  // ... then the right one slides 30 mm further right and the left one rolls 5 mm up.
  for (std::size_t q = 0; q < particles.size(); ++q) {
    if (particles.position[0][q] > 0.02) particles.position[0][q] += 0.03;
    else particles.position[2][q] += 0.005;
  }
  const std::vector<Piece> pieces = DetectPieces(LatticeOptions(), &particles);
  REQUIRE(pieces.size() == 2);
  const std::vector<double> cuts = CutPositionsAlongAxis(pieces, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  REQUIRE(cuts.size() == 1);
  CHECK(cuts[0] == Approx(0.021));
  // The world bounds moved with the pieces; the rest bounds did not.
  const Piece& right = pieces[0].centroid_m.x() > pieces[1].centroid_m.x() ? pieces[0] : pieces[1];
  CHECK(right.bounds_m.min().x() == Approx(0.054));
  CHECK(right.rest_bounds_m.min().x() == Approx(0.024));
}

TEST_CASE("float and double agree", "[mpm][topology]") {
  Particles<double> in_double;
  Particles<float> in_float;
  auto keep = [](int i, int j, int k) { return i % 7 != 3 && !(j == 2 && k > 3 && i > 10); };
  AddBlock(&in_double, {0.3, 0.1, 0.05}, 24, 6, 8, 0, keep);
  AddBlock(&in_float, {0.3, 0.1, 0.05}, 24, 6, 8, 0, keep);
  for (std::size_t p = 0; p < in_double.size(); p += 11) {
    in_double.damage[p] = 1.0;
    in_float.damage[p] = 1.0f;
  }
  const std::vector<Piece> pieces_double = DetectPieces(LatticeOptions(), &in_double);
  const std::vector<Piece> pieces_float = DetectPieces(LatticeOptions(), &in_float);
  REQUIRE(pieces_double.size() > 2);
  REQUIRE(pieces_float.size() == pieces_double.size());
  CHECK(in_float.piece == in_double.piece);
  for (std::size_t k = 0; k < pieces_double.size(); ++k) {
    CHECK(pieces_float[k].particle_count == pieces_double[k].particle_count);
    CHECK(pieces_float[k].volume_m3 == Approx(pieces_double[k].volume_m3).epsilon(1e-5));
    CHECK(pieces_float[k].centroid_m.isApprox(pieces_double[k].centroid_m, 1e-5));
  }
}

}  // namespace
}  // namespace culinarycut::mpm
