// Marching cubes: the closed, outward-oriented iso-surface of a density grid as an indexed
// triangle mesh. The 256 cube cases are generated (not typed in) from one rule per cube face, so
// neighbouring cubes always agree on the face they share and the surface has no cracks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/render/density_grid.h"
#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

// Cube numbering. Corner c sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cube's
// first node. Edge e runs along axis e / 4 from corner EdgeCorners(e)[0] to [1]; the bits of
// e % 4 give its offsets along the other two axes, lower axis first.
std::array<int, 2> EdgeCorners(int edge);

// Triangles per case; a case is the bit mask of the corners that are inside (density >= iso).
struct CubeCases {
  static constexpr int kMaxTriangles = 5;  // the builder checks it
  std::array<std::uint8_t, 256> triangle_count{};
  // Three cube edges per triangle, counter-clockwise seen from outside.
  std::array<std::array<std::uint8_t, 3 * kMaxTriangles>, 256> triangle_edges{};
};

// The case table, built once on first use (thread-safe). Face rule: where the inside corners of a
// face are diagonal, the inside is joined across the face (thin slices stay in one piece).
// Polygons are split into triangles whose added diagonals never join two points of one face,
// so every mesh edge is shared by exactly two triangles.
const CubeCases& MarchingCubesCases();

// Memory ExtractIsoSurface keeps between calls (overwritten each call).
struct IsoSurfaceScratch {
  std::vector<std::uint8_t> inside;                          // per node: density >= iso
  std::vector<std::uint8_t> row_kinds;                       // per row of nodes along x
  std::vector<std::uint32_t> row_vertices, row_triangles;    // counts, then running sums
  std::vector<std::vector<std::uint32_t>> layer_vertex_ids;  // per thread: two node layers
};

// Replaces `mesh` with the surface density = iso of `density`, with outward unit normals from the
// negated density gradient and, when `flesh_density` (same layout) is given, flesh = its share
// of the density at each vertex, clamped to [0, 1] (else 0). The surface is closed when the
// outermost node layer is below iso (DensityGridAround guarantees it). Vertices lie on grid edges,
// one per crossed edge, so the mesh is welded. Deterministic and independent of thread count.
// `mesh` keeps its memory (capacity) for the next call; so does `scratch` (optional). `threads`
// > 0 caps the OpenMP team.
void ExtractIsoSurface(const DensityGrid& density, float iso, const DensityGrid* flesh_density,
                       TriangleMesh* mesh, IsoSurfaceScratch* scratch = nullptr, int threads = 0);

}  // namespace culinarycut::render
