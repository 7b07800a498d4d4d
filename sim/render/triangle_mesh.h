// An indexed triangle mesh in the world frame, ready to upload: what surface extraction produces
// and what the renderer draws. Plain data.
#pragma once

#include <cstdint>
#include <vector>

namespace culinarycut::render {

struct TriangleMesh {
  std::vector<float> positions_m;        // x, y, z per vertex (world frame, m)
  std::vector<float> normals;            // unit outward normal per vertex (x, y, z)
  std::vector<float> flesh;              // per vertex, 0 = skin, 1 = exposed flesh
  std::vector<std::uint32_t> indices;    // three per triangle, counter-clockwise seen from outside

  std::size_t vertex_count() const { return positions_m.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace culinarycut::render
