#include <omp.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "mesh_checks.h"
#include "sim/render/food_surface.h"

namespace culinarycut::render {
namespace {

using testing::ClosedMeshProblem;
using testing::EnclosedVolume;
using testing::MeshBounds;

constexpr double kPi = 3.14159265358979323846;
constexpr float kSpacingM = 0.002f;  // particle spacing of every test food

// Particles in the solver's structure-of-arrays layout, kSpacingM apart.
struct Cloud : ParticleArrays {
  Cloud() { spacing_m = kSpacingM; }

  void Add(const std::array<float, 3>& p, std::int32_t piece_label = 0,
           std::uint16_t object_index = 0, float damage_value = 0.0f) {
    x.push_back(p[0]);
    y.push_back(p[1]);
    z.push_back(p[2]);
    piece.push_back(piece_label);
    object.push_back(object_index);
    damage.push_back(damage_value);
  }
  // The solver reorders particles: so may the tests.
  void Shuffle(std::uint32_t seed) {
    std::vector<std::size_t> order(x.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937(seed));
    Cloud shuffled;
    for (std::size_t s : order) shuffled.Add({x[s], y[s], z[s]}, piece[s], object[s], damage[s]);
    *this = shuffled;
  }
};

// One particle per lattice cell of kSpacingM whose centre (lower_m + (i + 1/2) spacing) passes
// `keep`, moved by up to +-jitter spacings per axis: the food then fills exactly its cells.
using SiteFilter =
    std::function<bool(const std::array<float, 3>& centre_m, const std::array<int, 3>& site)>;
void AddLattice(
    Cloud* cloud, const std::array<float, 3>& lower_m, const std::array<int, 3>& sites,
    float jitter, std::uint32_t seed, const SiteFilter& keep,
    const std::function<void(const std::array<int, 3>&, std::int32_t*, float*)>& label = nullptr,
    std::uint16_t object = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> offset(-jitter * kSpacingM, jitter * kSpacingM);
  for (int k = 0; k < sites[2]; ++k) {
    for (int j = 0; j < sites[1]; ++j) {
      for (int i = 0; i < sites[0]; ++i) {
        const std::array<int, 3> site = {i, j, k};
        std::array<float, 3> centre;
        for (int a = 0; a < 3; ++a) centre[a] = lower_m[a] + (site[a] + 0.5f) * kSpacingM;
        if (!keep(centre, site)) continue;
        std::int32_t piece = 0;
        float damage = 0.0f;
        if (label) label(site, &piece, &damage);
        cloud->Add({centre[0] + offset(rng), centre[1] + offset(rng), centre[2] + offset(rng)},
                   piece, object, damage);
      }
    }
  }
}

// A ball of radius `radius_m` at `centre_m`, jittered by a quarter spacing.
void AddBall(Cloud* cloud, const std::array<float, 3>& centre_m, float radius_m, std::uint32_t seed,
             std::uint16_t object = 0) {
  const int sites = static_cast<int>(std::ceil(2.0f * radius_m / kSpacingM)) + 2;
  const std::array<float, 3> lower = {centre_m[0] - 0.5f * sites * kSpacingM,
                                      centre_m[1] - 0.5f * sites * kSpacingM,
                                      centre_m[2] - 0.5f * sites * kSpacingM};
  const SiteFilter inside_ball = [&](const std::array<float, 3>& c, const std::array<int, 3>&) {
    const float dx = c[0] - centre_m[0], dy = c[1] - centre_m[1], dz = c[2] - centre_m[2];
    return dx * dx + dy * dy + dz * dz < radius_m * radius_m;
  };
  AddLattice(cloud, lower, {sites, sites, sites}, 0.25f, seed, inside_ball, nullptr, object);
}

const SiteFilter kAll = [](const std::array<float, 3>&, const std::array<int, 3>&) { return true; };

void CheckUnitNormals(const TriangleMesh& mesh) {
  REQUIRE(mesh.normals.size() == mesh.positions_m.size());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float* n = &mesh.normals[3 * v];
    REQUIRE(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] == Approx(1.0f).margin(1e-4));
  }
}

TEST_CASE("Food surface: a jittered ball gives one closed sphere with outward normals") {
  const std::array<float, 3> centre = {0.131f, -0.052f, 0.313f};
  const float radius = 10 * kSpacingM;
  Cloud cloud;
  AddBall(&cloud, centre, radius, 11);
  const std::vector<FoodPieceSurface> surfaces = ExtractFoodSurfaces(cloud.View());
  REQUIRE(surfaces.size() == 1);
  CHECK(surfaces[0].object == 0);
  CHECK(surfaces[0].piece == 0);
  CHECK(surfaces[0].particle_count == cloud.x.size());
  const TriangleMesh& mesh = surfaces[0].mesh;
  REQUIRE(mesh.triangle_count() > 500);
  CHECK(ClosedMeshProblem(mesh) == "");
  CheckUnitNormals(mesh);

  // The particles fill the ball's cells: the surface must enclose the ball, centred on it.
  const testing::VolumeAndCentroid measured = EnclosedVolume(mesh);
  CHECK(measured.volume == Approx(4.0 / 3.0 * kPi * std::pow(radius, 3)).epsilon(0.03));
  for (int a = 0; a < 3; ++a)
    CHECK(measured.centroid[a] == Approx(centre[a]).margin(0.1 * kSpacingM));

  double mean_radius = 0.0, mean_alignment = 0.0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    std::array<double, 3> d;
    double r = 0.0, along = 0.0;
    for (int a = 0; a < 3; ++a) {
      d[a] = mesh.positions_m[3 * v + a] - centre[a];
      r += d[a] * d[a];
    }
    r = std::sqrt(r);
    for (int a = 0; a < 3; ++a) along += mesh.normals[3 * v + a] * d[a] / r;
    REQUIRE(along > 0.0);  // every normal points out of the ball
    // Jitter roughens the surface locally; on average it sits on the ball.
    CHECK(r == Approx(radius).margin(0.75 * kSpacingM));
    mean_radius += r / mesh.vertex_count();
    mean_alignment += along / mesh.vertex_count();
  }
  CHECK(mean_radius == Approx(radius).margin(0.1 * kSpacingM));
  CHECK(mean_alignment > 0.97);
}

// A box's sharp edges come out bevelled by about one cell (the density there is 0.25 of full, below
// iso): a loss of about half a cell squared per metre of edge, 1.3 % of this box.
TEST_CASE("Food surface: a box of particles gives the box, half a spacing beyond its particles") {
  const std::array<float, 3> lower = {-0.1f, 0.05f, 0.2f};
  const std::array<int, 3> sites = {40, 20, 16};
  Cloud cloud;
  AddLattice(&cloud, lower, sites, 0.0f, 1, kAll);
  const std::vector<FoodPieceSurface> surfaces = ExtractFoodSurfaces(cloud.View());
  REQUIRE(surfaces.size() == 1);
  const TriangleMesh& mesh = surfaces[0].mesh;
  CHECK(ClosedMeshProblem(mesh) == "");
  CheckUnitNormals(mesh);
  const double box_volume = double(sites[0]) * sites[1] * sites[2] * std::pow(kSpacingM, 3);
  CHECK(EnclosedVolume(mesh).volume == Approx(box_volume).epsilon(0.03));
  const auto bounds = MeshBounds(mesh);
  for (int a = 0; a < 3; ++a) {
    CHECK(bounds[0][a] == Approx(lower[a]).margin(0.2 * kSpacingM));
    CHECK(bounds[1][a] == Approx(lower[a] + sites[a] * kSpacingM).margin(0.2 * kSpacingM));
  }
}

TEST_CASE("Food surface: two separated pieces give two closed surfaces that do not overlap") {
  // A 40-site bar cut at site 20; the right half (piece 7) moved 4 spacings away from piece 3.
  const std::array<int, 3> sites = {40, 16, 16};
  Cloud cloud;
  AddLattice(&cloud, {0.0f, 0.0f, 0.0f}, sites, 0.25f, 5, kAll,
             [](const std::array<int, 3>& site, std::int32_t* piece, float*) {
               *piece = site[0] < 20 ? 3 : 7;
             });
  for (std::size_t p = 0; p < cloud.x.size(); ++p) {
    if (cloud.piece[p] == 7) cloud.x[p] += 4 * kSpacingM;
  }
  cloud.Shuffle(9);
  const std::vector<FoodPieceSurface> surfaces = ExtractFoodSurfaces(cloud.View());
  REQUIRE(surfaces.size() == 2);
  CHECK(surfaces[0].piece == 3);
  CHECK(surfaces[1].piece == 7);
  const double half_volume = 20.0 * 16 * 16 * std::pow(kSpacingM, 3);
  for (const FoodPieceSurface& surface : surfaces) {
    CHECK(surface.particle_count == 5120);
    CHECK(ClosedMeshProblem(surface.mesh) == "");
    CHECK(EnclosedVolume(surface.mesh).volume == Approx(half_volume).epsilon(0.04));
  }
  const auto left = MeshBounds(surfaces[0].mesh), right = MeshBounds(surfaces[1].mesh);
  CHECK(left[1][0] < right[0][0]);
  CHECK(left[1][0] == Approx(20 * kSpacingM).margin(0.5 * kSpacingM));
  CHECK(right[0][0] == Approx(24 * kSpacingM).margin(0.5 * kSpacingM));
}

TEST_CASE("Food surface: damaged particles on a cut face show flesh, the outside shows skin") {
  // A bar whose +x end is a fresh cut: its last two particle layers are damaged; the rest carries
  // damage below the threshold, which must still read as skin.
  const std::array<int, 3> sites = {20, 12, 12};
  Cloud cloud;
  AddLattice(&cloud, {0.0f, 0.0f, 0.0f}, sites, 0.2f, 21, kAll,
             [](const std::array<int, 3>& site, std::int32_t*, float* damage) {
               *damage = site[0] >= 18 ? 0.9f : 0.02f;
             });
  FoodSurfaceOptions options;
  options.flesh_damage = 0.05f;
  const std::vector<FoodPieceSurface> surfaces = ExtractFoodSurfaces(cloud.View(), options);
  REQUIRE(surfaces.size() == 1);
  const TriangleMesh& mesh = surfaces[0].mesh;
  REQUIRE(mesh.flesh.size() == mesh.vertex_count());
  const float end = sites[0] * kSpacingM, side = sites[1] * kSpacingM;
  int cut_face_vertices = 0, far_vertices = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float* p = &mesh.positions_m[3 * v];
    const float flesh = mesh.flesh[v];
    REQUIRE(flesh >= 0.0f);
    REQUIRE(flesh <= 1.0f);
    const bool away_from_rim = p[1] > 2 * kSpacingM && p[1] < side - 2 * kSpacingM &&
                               p[2] > 2 * kSpacingM && p[2] < side - 2 * kSpacingM;
    if (p[0] > end - 0.25f * kSpacingM && away_from_rim) {
      CHECK(flesh > 0.9f);
      ++cut_face_vertices;
    }
    // Two particle layers plus the kernel's reach from the damaged band: skin only.
    if (p[0] < end - 4 * kSpacingM) {
      CHECK(flesh == 0.0f);
      ++far_vertices;
    }
  }
  CHECK(cut_face_vertices > 20);
  CHECK(far_vertices > 200);

  // Without damage everything is skin.
  Cloud undamaged = cloud;
  std::fill(undamaged.damage.begin(), undamaged.damage.end(), 0.0f);
  ParticleView no_damage = cloud.View();
  no_damage.damage = nullptr;
  for (const ParticleView& view : {undamaged.View(), no_damage}) {
    const std::vector<FoodPieceSurface> skin_only = ExtractFoodSurfaces(view);
    REQUIRE(skin_only.size() == 1);
    REQUIRE(skin_only[0].mesh.positions_m == mesh.positions_m);
    for (float flesh : skin_only[0].mesh.flesh) REQUIRE(flesh == 0.0f);
  }
}

TEST_CASE("Food surface: objects are kept apart, output in ascending object then piece order") {
  // Object 1 (a ball) overlaps object 0 (a box) in space, and comes first in memory.
  Cloud cloud;
  AddBall(&cloud, {0.02f, 0.01f, 0.01f}, 6 * kSpacingM, 3, 1);
  const std::size_t ball_particles = cloud.x.size();
  AddLattice(&cloud, {0.0f, 0.0f, 0.0f}, {12, 10, 10}, 0.0f, 1, kAll,
             [](const std::array<int, 3>& site, std::int32_t* piece, float*) {
               *piece = site[0] < 6 ? -1 : 2;  // -1: no piece label yet, which counts as piece 0
             });
  cloud.Shuffle(4);
  const std::vector<FoodPieceSurface> surfaces = ExtractFoodSurfaces(cloud.View());
  REQUIRE(surfaces.size() == 3);
  CHECK(surfaces[0].object == 0);
  CHECK(surfaces[0].piece == 0);
  CHECK(surfaces[0].particle_count == 600);
  CHECK(surfaces[1].object == 0);
  CHECK(surfaces[1].piece == 2);
  CHECK(surfaces[1].particle_count == 600);
  CHECK(surfaces[2].object == 1);
  CHECK(surfaces[2].piece == 0);
  CHECK(surfaces[2].particle_count == ball_particles);
  for (const FoodPieceSurface& surface : surfaces) CHECK(ClosedMeshProblem(surface.mesh) == "");
  const double ball_volume = ball_particles * std::pow(kSpacingM, 3);
  CHECK(EnclosedVolume(surfaces[2].mesh).volume == Approx(ball_volume).epsilon(0.05));
}

TEST_CASE("Food surface: same input gives the same bits, for one thread and for two") {
  Cloud cloud;
  AddBall(&cloud, {0.0f, 0.0f, 0.0f}, 18 * kSpacingM, 8);  // enough particles to go parallel
  for (std::size_t p = 0; p < cloud.x.size(); ++p) {
    cloud.piece[p] = cloud.x[p] < 0.0f ? 0 : 1;
    cloud.damage[p] = std::abs(cloud.x[p]) < 2 * kSpacingM ? 1.0f : 0.0f;
  }
  REQUIRE(cloud.x.size() > 20000);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<FoodPieceSurface> one = ExtractFoodSurfaces(cloud.View());
  omp_set_num_threads(2);
  const std::vector<FoodPieceSurface> two = ExtractFoodSurfaces(cloud.View());
  const std::vector<FoodPieceSurface> again = ExtractFoodSurfaces(cloud.View());
  FoodSurfaceOptions capped;
  capped.max_threads = 1;
  const std::vector<FoodPieceSurface> one_by_option = ExtractFoodSurfaces(cloud.View(), capped);
  omp_set_num_threads(threads);
  REQUIRE(one.size() == 2);
  for (const auto* other : {&two, &again, &one_by_option}) {
    REQUIRE(other->size() == 2);
    for (std::size_t s = 0; s < 2; ++s) {
      CHECK(one[s].mesh.positions_m == (*other)[s].mesh.positions_m);
      CHECK(one[s].mesh.normals == (*other)[s].mesh.normals);
      CHECK(one[s].mesh.flesh == (*other)[s].mesh.flesh);
      CHECK(one[s].mesh.indices == (*other)[s].mesh.indices);
    }
  }
}

TEST_CASE("Food surface: particle order changes no more than round-off") {
  Cloud cloud;
  AddBall(&cloud, {0.01f, 0.02f, 0.03f}, 8 * kSpacingM, 2);
  const TriangleMesh before = ExtractFoodSurfaces(cloud.View())[0].mesh;
  cloud.Shuffle(77);
  const TriangleMesh after = ExtractFoodSurfaces(cloud.View())[0].mesh;
  REQUIRE(after.indices == before.indices);
  for (std::size_t i = 0; i < before.positions_m.size(); ++i) {
    REQUIRE(after.positions_m[i] == Approx(before.positions_m[i]).margin(1e-6));
  }
}

TEST_CASE("Food surface: a grid coarser than the particles still encloses the food") {
  Cloud cloud;
  const float radius = 12 * kSpacingM;
  AddBall(&cloud, {0.0f, 0.0f, 0.0f}, radius, 6);
  FoodSurfaceOptions options;
  options.cell_size_m = 2 * kSpacingM;
  const TriangleMesh mesh = ExtractFoodSurfaces(cloud.View(), options)[0].mesh;
  CHECK(ClosedMeshProblem(mesh) == "");
  CHECK(EnclosedVolume(mesh).volume == Approx(4.0 / 3.0 * kPi * std::pow(radius, 3)).epsilon(0.05));
}

TEST_CASE("Food surface: an explicit cell size stands in for a missing particle spacing") {
  Cloud cloud;
  AddBall(&cloud, {0.0f, 0.0f, 0.0f}, 6 * kSpacingM, 12);
  FoodSurfaceOptions options;
  options.cell_size_m = kSpacingM;
  ParticleView no_spacing = cloud.View();
  no_spacing.particle_spacing_m = 0.0f;
  const TriangleMesh with = ExtractFoodSurfaces(cloud.View(), options)[0].mesh;
  const TriangleMesh without = ExtractFoodSurfaces(no_spacing, options)[0].mesh;
  CHECK(with.triangle_count() > 0);
  CHECK(with.positions_m == without.positions_m);
  CHECK(with.indices == without.indices);
}

TEST_CASE("Food surface: a lone particle is too thin to show, a crumb of eight is a closed blob") {
  // One particle peaks at 0.75^3 = 0.42 of a filled cell, below the iso level of 0.5.
  Cloud lone;
  lone.Add({0.01f, 0.02f, 0.03f}, 4);
  const std::vector<FoodPieceSurface> lone_surfaces = ExtractFoodSurfaces(lone.View());
  REQUIRE(lone_surfaces.size() == 1);
  CHECK(lone_surfaces[0].piece == 4);
  CHECK(lone_surfaces[0].particle_count == 1);
  CHECK(lone_surfaces[0].mesh.triangle_count() == 0);

  Cloud crumb;
  AddLattice(&crumb, {0.01f, 0.02f, 0.03f}, {2, 2, 2}, 0.0f, 1, kAll);
  const TriangleMesh mesh = ExtractFoodSurfaces(crumb.View())[0].mesh;
  REQUIRE(mesh.triangle_count() > 0);
  CHECK(ClosedMeshProblem(mesh) == "");
  CHECK(EnclosedVolume(mesh).volume > 0.0);
  CHECK(EnclosedVolume(mesh).volume < 8 * std::pow(kSpacingM, 3));
}

TEST_CASE("Food surface: a reused workspace gives what fresh memory gives") {
  Cloud ball, bar;
  AddBall(&ball, {0.0f, 0.0f, 0.0f}, 9 * kSpacingM, 5);
  AddLattice(&bar, {0.1f, 0.0f, 0.0f}, {30, 8, 8}, 0.2f, 6, kAll,
             [](const std::array<int, 3>& site, std::int32_t* piece, float* damage) {
               *piece = site[0] < 15 ? 0 : 1;
               *damage = site[0] == 14 || site[0] == 15 ? 1.0f : 0.0f;
             });
  FoodSurfaceWorkspace workspace;
  std::vector<FoodPieceSurface> reused;
  // Big, then small, then big again: stale memory from a larger call must not leak through.
  for (const Cloud* cloud : {&bar, &ball, &bar, &ball}) {
    ExtractFoodSurfaces(cloud->View(), {}, &workspace, &reused);
    const std::vector<FoodPieceSurface> fresh = ExtractFoodSurfaces(cloud->View());
    REQUIRE(reused.size() == fresh.size());
    for (std::size_t s = 0; s < fresh.size(); ++s) {
      CHECK(reused[s].object == fresh[s].object);
      CHECK(reused[s].piece == fresh[s].piece);
      CHECK(reused[s].particle_count == fresh[s].particle_count);
      CHECK(reused[s].mesh.positions_m == fresh[s].mesh.positions_m);
      CHECK(reused[s].mesh.normals == fresh[s].mesh.normals);
      CHECK(reused[s].mesh.flesh == fresh[s].mesh.flesh);
      CHECK(reused[s].mesh.indices == fresh[s].mesh.indices);
    }
  }
  // A failed call leaves the previous result in place.
  Cloud broken = ball;
  broken.x[3] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(ExtractFoodSurfaces(broken.View(), {}, &workspace, &reused),
                  std::invalid_argument);
  CHECK(reused.size() == 1);
  CHECK(reused[0].mesh.triangle_count() > 0);
}

TEST_CASE("Food surface: empty input gives no surfaces") {
  CHECK(ExtractFoodSurfaces(ParticleView{}).empty());
  Cloud cloud;
  CHECK(ExtractFoodSurfaces(cloud.View()).empty());
}

TEST_CASE("Food surface: bad input is refused with a message that says what to fix") {
  Cloud cloud;
  AddBall(&cloud, {0.0f, 0.0f, 0.0f}, 4 * kSpacingM, 1);
  const auto message_of = [](const ParticleView& view, const FoodSurfaceOptions& options) {
    try {
      ExtractFoodSurfaces(view, options);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  using Catch::Matchers::Contains;

  SECTION("non-finite position") {
    cloud.y[5] = std::numeric_limits<float>::quiet_NaN();
    CHECK_THAT(message_of(cloud.View(), {}), Contains("particle 5") && Contains("non-finite"));
    cloud.y[5] = 0.0f;
    cloud.z[9] = std::numeric_limits<float>::infinity();
    CHECK_THAT(message_of(cloud.View(), {}), Contains("particle 9"));
  }
  SECTION("no spacing and no cell size") {
    ParticleView view = cloud.View();
    view.particle_spacing_m = 0.0f;
    CHECK_THAT(message_of(view, {}), Contains("particle_spacing_m") && Contains("cell_size_m"));
    view.particle_spacing_m = -0.002f;
    CHECK_THAT(message_of(view, {}), Contains("particle_spacing_m"));
    FoodSurfaceOptions with_cell;
    with_cell.cell_size_m = 0.002f;
    view.particle_spacing_m = std::numeric_limits<float>::infinity();
    CHECK_THAT(message_of(view, with_cell), Contains("particle_spacing_m"));
  }
  SECTION("grid larger than allowed") {
    FoodSurfaceOptions options;
    options.max_grid_cells = 1000;
    CHECK_THAT(message_of(cloud.View(), options), Contains("max_grid_cells"));
    // One particle thrown 50 m away stretches the piece's grid beyond the default limit.
    cloud.x[0] = cloud.y[0] = cloud.z[0] = 50.0f;
    CHECK_THAT(message_of(cloud.View(), {}),
               Contains("object 0 piece 0") && Contains("cell_size_m"));
  }
  SECTION("bad options and missing arrays") {
    FoodSurfaceOptions options;
    options.iso_level = 0.0f;
    CHECK_THAT(message_of(cloud.View(), options), Contains("iso_level"));
    options = {};
    options.max_threads = -1;
    CHECK_THAT(message_of(cloud.View(), options), Contains("max_threads"));
    options = {};
    options.cell_size_m = -1.0f;
    CHECK_THAT(message_of(cloud.View(), options), Contains("cell_size_m"));
    ParticleView view = cloud.View();
    view.y_m = nullptr;
    CHECK_THAT(message_of(view, {}), Contains("null"));
  }
}

}  // namespace
}  // namespace culinarycut::render
