#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <vector>

#include "mesh_checks.h"
#include "sim/render/marching_cubes.h"

namespace culinarycut::render {
namespace {

using testing::ClosedMeshProblem;
using testing::EnclosedVolume;

constexpr double kPi = 3.14159265358979323846;

DensityGrid EmptyGrid(int nodes, float cell_m, std::array<float, 3> origin_m = {0, 0, 0}) {
  DensityGrid grid;
  grid.origin_m = origin_m;
  grid.cell_size_m = cell_m;
  grid.nodes = {nodes, nodes, nodes};
  grid.values.assign(grid.node_count(), 0.0f);
  return grid;
}

bool CornerInside(int mask, int corner) { return (mask >> corner) & 1; }

TEST_CASE("Cube cases: only cubes the surface crosses get triangles, built from crossed edges") {
  const CubeCases& cases = MarchingCubesCases();
  CHECK(cases.triangle_count[0] == 0);
  CHECK(cases.triangle_count[255] == 0);
  for (int mask = 1; mask < 255; ++mask) {
    INFO("case " << mask);
    std::set<int> crossed, used;
    for (int e = 0; e < 12; ++e) {
      const std::array<int, 2> c = EdgeCorners(e);
      if (CornerInside(mask, c[0]) != CornerInside(mask, c[1])) crossed.insert(e);
    }
    for (int v = 0; v < 3 * cases.triangle_count[mask]; ++v)
      used.insert(cases.triangle_edges[mask][v]);
    CHECK(used == crossed);
    // A polygon of k crossed edges needs k - 2 triangles; loops have at least three edges.
    CHECK(cases.triangle_count[mask] <= static_cast<int>(crossed.size()) - 2);
    CHECK(cases.triangle_count[mask] >= static_cast<int>(crossed.size()) / 3);
  }
}

TEST_CASE("Cube cases: a lone inside corner is cut off by one triangle facing away from it") {
  const CubeCases& cases = MarchingCubesCases();
  for (int corner = 0; corner < 8; ++corner) {
    for (int inverted = 0; inverted < 2; ++inverted) {
      const int mask = inverted ? 255 ^ (1 << corner) : 1 << corner;
      REQUIRE(cases.triangle_count[mask] == 1);
      // Triangle normal from edge midpoints, against the direction from the corner to the centre.
      std::array<std::array<float, 3>, 3> p;
      for (int v = 0; v < 3; ++v) {
        const std::array<int, 2> c = EdgeCorners(cases.triangle_edges[mask][v]);
        for (int a = 0; a < 3; ++a) p[v][a] = 0.5f * (((c[0] >> a) & 1) + ((c[1] >> a) & 1));
      }
      const std::array<float, 3> u = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
      const std::array<float, 3> w = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
      const std::array<float, 3> normal = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                           u[0] * w[1] - u[1] * w[0]};
      float toward_centre = 0.0f;
      for (int a = 0; a < 3; ++a) toward_centre += normal[a] * (0.5f - float((corner >> a) & 1));
      // Outside is towards the centre when the corner is inside, away from it when inverted.
      CHECK((inverted ? toward_centre < 0.0f : toward_centre > 0.0f));
    }
  }
}

TEST_CASE("Marching cubes: random fields give closed, consistently oriented surfaces") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  std::set<int> cases_seen;
  for (int trial = 0; trial < 40; ++trial) {
    DensityGrid grid = EmptyGrid(10, 0.01f, {0.1f * trial, -0.2f, 0.3f});
    for (int k = 1; k < 9; ++k) {
      for (int j = 1; j < 9; ++j) {
        for (int i = 1; i < 9; ++i) grid.values[grid.index(i, j, k)] = value(rng);
      }
    }
    for (int k = 0; k < 9; ++k) {
      for (int j = 0; j < 9; ++j) {
        for (int i = 0; i < 9; ++i) {
          int mask = 0;
          for (int c = 0; c < 8; ++c) {
            const int n = grid.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
            mask |= (grid.values[n] >= 0.5f) << c;
          }
          cases_seen.insert(mask);
        }
      }
    }
    TriangleMesh mesh;
    ExtractIsoSurface(grid, 0.5f, nullptr, &mesh);
    INFO("trial " << trial);
    REQUIRE(mesh.triangle_count() > 0);
    CHECK(ClosedMeshProblem(mesh) == "");
    CHECK(EnclosedVolume(mesh).volume > 0.0);
    CHECK(mesh.normals.size() == mesh.positions_m.size());
    CHECK(mesh.flesh.size() == mesh.vertex_count());
  }
  // The fields must have exercised every case for the check above to cover the table.
  CHECK(cases_seen.size() == 256);
}

TEST_CASE("Marching cubes: a sphere field gives a sphere with radial outward normals") {
  const float cell = 0.002f, radius = 0.016f;  // m
  const std::array<float, 3> centre = {0.0251f, 0.0247f, 0.0253f};
  DensityGrid grid = EmptyGrid(26, cell);
  for (int k = 0; k < 26; ++k) {
    for (int j = 0; j < 26; ++j) {
      for (int i = 0; i < 26; ++i) {
        const float dx = i * cell - centre[0], dy = j * cell - centre[1], dz = k * cell - centre[2];
        grid.values[grid.index(i, j, k)] = radius - std::sqrt(dx * dx + dy * dy + dz * dz);
      }
    }
  }
  TriangleMesh mesh;
  ExtractIsoSurface(grid, 0.0f, nullptr, &mesh);
  REQUIRE(ClosedMeshProblem(mesh) == "");
  double worst_radius_error = 0.0, worst_alignment = 1.0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    double d[3], r = 0.0, along = 0.0, length = 0.0;
    for (int a = 0; a < 3; ++a) {
      d[a] = mesh.positions_m[3 * v + a] - centre[a];
      r += d[a] * d[a];
      length += double(mesh.normals[3 * v + a]) * mesh.normals[3 * v + a];
    }
    r = std::sqrt(r);
    for (int a = 0; a < 3; ++a) along += mesh.normals[3 * v + a] * d[a] / r;
    worst_radius_error = std::max(worst_radius_error, std::abs(r - radius));
    worst_alignment = std::min(worst_alignment, along);
    REQUIRE(length == Approx(1.0).margin(1e-5));
  }
  // Linear interpolation of a distance field along an edge errs by at most cell^2 / (8 radius).
  CHECK(worst_radius_error < 0.02 * cell);
  CHECK(worst_alignment > 0.995);
  const testing::VolumeAndCentroid measured = EnclosedVolume(mesh);
  CHECK(measured.volume == Approx(4.0 / 3.0 * kPi * std::pow(radius, 3)).epsilon(0.02));
  for (int a = 0; a < 3; ++a) CHECK(measured.centroid[a] == Approx(centre[a]).margin(1e-5));
}

TEST_CASE("Marching cubes: flesh is the flesh density's share of the density at each vertex") {
  DensityGrid density = EmptyGrid(8, 0.001f);
  DensityGrid flesh = density;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (int k = 1; k < 7; ++k) {
    for (int j = 1; j < 7; ++j) {
      for (int i = 1; i < 7; ++i) {
        const std::size_t n = density.index(i, j, k);
        density.values[n] = value(rng);
        // Flesh grows from none at i = 1 to all of the density at i = 6.
        flesh.values[n] = density.values[n] * (i - 1) / 5.0f;
      }
    }
  }
  TriangleMesh with_flesh, without_flesh;
  ExtractIsoSurface(density, 0.5f, &flesh, &with_flesh);
  ExtractIsoSurface(density, 0.5f, nullptr, &without_flesh);
  REQUIRE(with_flesh.vertex_count() > 0);
  CHECK(with_flesh.positions_m == without_flesh.positions_m);
  CHECK(with_flesh.indices == without_flesh.indices);
  float lowest = 1.0f, highest = 0.0f;
  for (std::size_t v = 0; v < with_flesh.vertex_count(); ++v) {
    CHECK(without_flesh.flesh[v] == 0.0f);
    CHECK(with_flesh.flesh[v] >= 0.0f);
    CHECK(with_flesh.flesh[v] <= 1.0f);
    const float x_cells = with_flesh.positions_m[3 * v] / density.cell_size_m;
    lowest = std::min(lowest, with_flesh.flesh[v]);
    highest = std::max(highest, with_flesh.flesh[v]);
    // Where both ends of the vertex's edge sit in one x layer the share is exact.
    if (std::abs(x_cells - std::round(x_cells)) < 1e-4f) {
      CHECK(with_flesh.flesh[v] == Approx((std::round(x_cells) - 1.0f) / 5.0f).margin(1e-4));
    }
  }
  CHECK(lowest < 0.05f);
  CHECK(highest > 0.95f);
}

// Connected pieces of a mesh: triangles that share a vertex belong together.
int ComponentCount(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> parent(mesh.vertex_count());
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  const std::function<std::uint32_t(std::uint32_t)> root = [&](std::uint32_t v) {
    return parent[v] == v ? v : parent[v] = root(parent[v]);
  };
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    parent[root(mesh.indices[i + 1])] = root(mesh.indices[i]);
    parent[root(mesh.indices[i + 2])] = root(mesh.indices[i]);
  }
  int roots = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v) roots += root(v) == v;
  return roots;
}

TEST_CASE("Marching cubes: inside corners diagonal on a face are joined across it") {
  // Two inside nodes touching only along a face diagonal: one blob, not two.
  DensityGrid grid = EmptyGrid(5, 0.001f);
  grid.values[grid.index(2, 2, 2)] = 1.0f;
  grid.values[grid.index(3, 3, 2)] = 1.0f;
  TriangleMesh mesh;
  ExtractIsoSurface(grid, 0.5f, nullptr, &mesh);
  CHECK(ClosedMeshProblem(mesh) == "");
  CHECK(ComponentCount(mesh) == 1);
  // Touching only at a cube's corner (body diagonal): two blobs.
  grid.values[grid.index(3, 3, 2)] = 0.0f;
  grid.values[grid.index(3, 3, 3)] = 1.0f;
  ExtractIsoSurface(grid, 0.5f, nullptr, &mesh);
  CHECK(ClosedMeshProblem(mesh) == "");
  CHECK(ComponentCount(mesh) == 2);
}

TEST_CASE("Marching cubes: a grid with nothing above iso gives an empty mesh") {
  DensityGrid grid = EmptyGrid(6, 0.001f);
  grid.values[grid.index(3, 3, 3)] = 0.4f;
  TriangleMesh mesh;
  mesh.indices = {0, 1, 2};  // stale content must go
  ExtractIsoSurface(grid, 0.5f, nullptr, &mesh);
  CHECK(mesh.vertex_count() == 0);
  CHECK(mesh.triangle_count() == 0);
}

}  // namespace
}  // namespace culinarycut::render
