// Known-answer measures of a triangle mesh for the surface tests: closedness, volume, centroid.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "sim/render/triangle_mesh.h"

namespace culinarycut::render::testing {

// Empty when every edge is used once in each direction (closed and consistently oriented),
// otherwise what is wrong with the first offending edge.
inline std::string ClosedMeshProblem(const TriangleMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const std::uint32_t* v = &mesh.indices[3 * t];
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) return "triangle with a repeated vertex";
    for (int e = 0; e < 3; ++e) {
      if (v[e] >= mesh.vertex_count()) return "index out of range";
      ++directed[{v[e], v[(e + 1) % 3]}];
    }
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return "directed edge used " + std::to_string(count) + " times";
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end()) return "edge with one triangle (hole or flipped triangle)";
  }
  return "";
}

// Volume (m^3) and volume centroid (m) by the divergence theorem: positive for an outward mesh.
struct VolumeAndCentroid {
  double volume = 0.0;
  std::array<double, 3> centroid{};
};

inline VolumeAndCentroid EnclosedVolume(const TriangleMesh& mesh) {
  VolumeAndCentroid result;
  // Tetrahedra from a point near the mesh keep the sums well conditioned.
  const std::array<double, 3> o = {mesh.positions_m[0], mesh.positions_m[1], mesh.positions_m[2]};
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    std::array<std::array<double, 3>, 3> p;
    for (int v = 0; v < 3; ++v) {
      for (int a = 0; a < 3; ++a)
        p[v][a] = mesh.positions_m[3 * mesh.indices[3 * t + v] + a] - o[a];
    }
    const double six_volume = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                              p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                              p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    result.volume += six_volume / 6.0;
    for (int a = 0; a < 3; ++a) {
      result.centroid[a] += six_volume / 6.0 * (p[0][a] + p[1][a] + p[2][a]) / 4.0;
    }
  }
  for (int a = 0; a < 3; ++a) result.centroid[a] = result.centroid[a] / result.volume + o[a];
  return result;
}

// Axis-aligned bounds of the vertices (m): lower then upper.
inline std::array<std::array<float, 3>, 2> MeshBounds(const TriangleMesh& mesh) {
  std::array<std::array<float, 3>, 2> bounds = {{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}}};
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    for (int a = 0; a < 3; ++a) {
      bounds[0][a] = std::min(bounds[0][a], mesh.positions_m[3 * v + a]);
      bounds[1][a] = std::max(bounds[1][a], mesh.positions_m[3 * v + a]);
    }
  }
  return bounds;
}

}  // namespace culinarycut::render::testing
