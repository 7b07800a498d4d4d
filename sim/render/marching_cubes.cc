#include "sim/render/marching_cubes.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace culinarycut::render {
namespace {

using Vec3 = std::array<float, 3>;

// Below this many grid nodes threads cost more than they save.
constexpr std::size_t kParallelNodes = 32768;

Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
float Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

int CornerBit(int corner, int axis) { return (corner >> axis) & 1; }

Vec3 CornerPosition(int corner) {
  return {float(CornerBit(corner, 0)), float(CornerBit(corner, 1)), float(CornerBit(corner, 2))};
}

Vec3 EdgeMidpoint(int edge) {
  const std::array<int, 2> c = EdgeCorners(edge);
  const Vec3 a = CornerPosition(c[0]), b = CornerPosition(c[1]);
  return {0.5f * (a[0] + b[0]), 0.5f * (a[1] + b[1]), 0.5f * (a[2] + b[2])};
}

// Face f is the cube side across axis f / 2 at coordinate f % 2.
bool EdgeOnFace(int edge, int face) {
  const int axis = face / 2, side = face % 2;
  const std::array<int, 2> c = EdgeCorners(edge);
  return edge / 4 != axis && CornerBit(c[0], axis) == side && CornerBit(c[1], axis) == side;
}

bool ShareFace(int edge_a, int edge_b) {
  for (int face = 0; face < 6; ++face) {
    if (EdgeOnFace(edge_a, face) && EdgeOnFace(edge_b, face)) return true;
  }
  return false;
}

// The corner two edges share, or -1.
int SharedCorner(int edge_a, int edge_b) {
  for (int ca : EdgeCorners(edge_a)) {
    for (int cb : EdgeCorners(edge_b)) {
      if (ca == cb) return ca;
    }
  }
  return -1;
}

// The surface's boundary on the cube's faces, as closed loops of crossed edges, counter-clockwise
// seen from outside (right-hand rule with the outward normal).
std::vector<std::vector<int>> SurfaceLoops(int inside_mask) {
  const auto inside = [&](int corner) { return (inside_mask >> corner) & 1; };
  const auto crossed = [&](int edge) {
    const std::array<int, 2> c = EdgeCorners(edge);
    return inside(c[0]) != inside(c[1]);
  };
  std::array<int, 12> next;
  std::array<int, 12> incoming{};
  next.fill(-1);
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    Vec3 face_normal{0, 0, 0};  // outward from the cube
    face_normal[axis] = face % 2 ? 1.0f : -1.0f;
    std::vector<int> face_edges;
    for (int edge = 0; edge < 12; ++edge) {
      if (EdgeOnFace(edge, face) && crossed(edge)) face_edges.push_back(edge);
    }
    // Pair the crossed edges into segments; with four, each segment cuts off an outside corner.
    std::vector<std::array<int, 2>> segments;
    if (face_edges.size() == 2) {
      segments.push_back({face_edges[0], face_edges[1]});
    } else if (face_edges.size() == 4) {
      for (int corner = 0; corner < 8; ++corner) {
        if (CornerBit(corner, axis) != face % 2 || inside(corner)) continue;
        std::vector<int> around;
        for (int edge : face_edges) {
          const std::array<int, 2> c = EdgeCorners(edge);
          if (c[0] == corner || c[1] == corner) around.push_back(edge);
        }
        segments.push_back({around[0], around[1]});
      }
    }
    for (std::array<int, 2> segment : segments) {
      // g points from the inside corners to the outside ones within the face.
      const Vec3 a = EdgeMidpoint(segment[0]), b = EdgeMidpoint(segment[1]);
      const Vec3 mid{0.5f * (a[0] + b[0]), 0.5f * (a[1] + b[1]), 0.5f * (a[2] + b[2])};
      const int shared = SharedCorner(segment[0], segment[1]);
      Vec3 g;
      if (shared >= 0) {
        g = inside(shared) ? Sub(mid, CornerPosition(shared)) : Sub(CornerPosition(shared), mid);
      } else {
        const std::array<int, 2> c = EdgeCorners(segment[0]);
        g = Sub(mid, CornerPosition(inside(c[0]) ? c[0] : c[1]));
      }
      // Outward surface normal x face normal gives the boundary direction on this face.
      if (Dot(Sub(b, a), Cross(g, face_normal)) < 0) std::swap(segment[0], segment[1]);
      if (next[segment[0]] != -1) throw std::logic_error("marching cubes: edge leaves twice");
      next[segment[0]] = segment[1];
      ++incoming[segment[1]];
    }
  }
  std::vector<std::vector<int>> loops;
  std::array<bool, 12> visited{};
  for (int edge = 0; edge < 12; ++edge) {
    if (!crossed(edge)) continue;
    if (next[edge] < 0 || incoming[edge] != 1) {
      throw std::logic_error("marching cubes: open surface boundary in case " +
                             std::to_string(inside_mask));
    }
    if (visited[edge]) continue;
    std::vector<int> loop;
    for (int e = edge; !visited[e]; e = next[e]) {
      visited[e] = true;
      loop.push_back(e);
    }
    loops.push_back(loop);
  }
  return loops;
}

// Splits a loop into triangles, keeping its orientation, with no diagonal between two points of
// one cube face (the neighbouring cube could draw that same edge: an edge of four triangles).
bool Triangulate(const std::vector<int>& loop, std::vector<std::array<int, 3>>* triangles) {
  const std::size_t n = loop.size();
  if (n == 3) {
    triangles->push_back({loop[0], loop[1], loop[2]});
    return true;
  }
  // The triangle on side (loop[0], loop[1]) has its third corner at loop[k].
  for (std::size_t k = 2; k < n; ++k) {
    if (k > 2 && ShareFace(loop[1], loop[k])) continue;
    if (k < n - 1 && ShareFace(loop[k], loop[0])) continue;
    const std::size_t kept = triangles->size();
    triangles->push_back({loop[0], loop[1], loop[k]});
    const std::vector<int> first(loop.begin() + 1, loop.begin() + k + 1);
    std::vector<int> second(loop.begin() + k, loop.end());
    second.push_back(loop[0]);
    if ((first.size() < 3 || Triangulate(first, triangles)) &&
        (second.size() < 3 || Triangulate(second, triangles))) {
      return true;
    }
    triangles->resize(kept);
  }
  return false;
}

// Which kinds of node a row holds.
constexpr std::uint8_t kHasOutside = 1, kHasInside = 2;

// Number of i in [0, n) with a[i] != b[i]; flags are 0 or 1.
int CountDifferences(const std::uint8_t* a, const std::uint8_t* b, int n) {
  int count = 0;
  for (int i = 0; i < n; ++i) count += a[i] ^ b[i];
  return count;
}

// Calls visit(i) for each i in [0, n) with a[i] != b[i], ascending, eight flags at a time (byte i
// of a little-endian word is flag i).
template <typename Visit>
void ForEachDifference(const std::uint8_t* a, const std::uint8_t* b, int n, Visit&& visit) {
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t word_a, word_b;
    std::memcpy(&word_a, a + i, 8);
    std::memcpy(&word_b, b + i, 8);
    for (std::uint64_t diff = word_a ^ word_b; diff != 0; diff &= diff - 1) {
      visit(i + __builtin_ctzll(diff) / 8);
    }
  }
  for (; i < n; ++i) {
    if (a[i] != b[i]) visit(i);
  }
}

// Twice the density's derivative (per cell) along one axis at a node with index `at` of `nodes`
// on that axis: central difference, one-sided (doubled) on the grid's border.
inline float TwiceDerivative(const float* d, std::size_t node, std::size_t stride, int at,
                             int nodes) {
  const bool low = at > 0, high = at + 1 < nodes;
  if (low && high) return d[node + stride] - d[node - stride];
  if (!low && !high) return 0.0f;
  return 2.0f * (d[node + (high ? stride : 0)] - d[node - (low ? stride : 0)]);
}

// Writes vertex `id` where the density crosses iso on the grid edge from node ijk along `axis`:
// position by linear interpolation, outward normal from the negated density gradient, flesh share.
void AddVertex(const DensityGrid& density, const float* flesh, float iso,
               const std::array<int, 3>& ijk, int axis, std::uint32_t id, TriangleMesh* mesh) {
  const float* d = density.values.data();
  const std::size_t node = density.index(ijk[0], ijk[1], ijk[2]);
  const std::size_t strides[3] = {1, static_cast<std::size_t>(density.nodes[0]),
                                  static_cast<std::size_t>(density.nodes[0]) * density.nodes[1]};
  const std::size_t other = node + strides[axis];
  const float t = (iso - d[node]) / (d[other] - d[node]);  // in [0, 1]
  float* position = &mesh->positions_m[3 * static_cast<std::size_t>(id)];
  for (int c = 0; c < 3; ++c) position[c] = density.origin_m[c] + density.cell_size_m * ijk[c];
  position[axis] += density.cell_size_m * t;
  // The negated density gradient, interpolated along the edge, points out.
  Vec3 normal;
  const bool interior =
      ijk[0] > 0 && ijk[1] > 0 && ijk[2] > 0 && ijk[0] + 1 + (axis == 0) < density.nodes[0] &&
      ijk[1] + 1 + (axis == 1) < density.nodes[1] && ijk[2] + 1 + (axis == 2) < density.nodes[2];
  for (int c = 0; c < 3; ++c) {
    const std::size_t s = strides[c];
    const float g0 = interior ? d[node + s] - d[node - s]
                              : TwiceDerivative(d, node, s, ijk[c], density.nodes[c]);
    const float g1 = interior
                         ? d[other + s] - d[other - s]
                         : TwiceDerivative(d, other, s, ijk[c] + (c == axis), density.nodes[c]);
    normal[c] = g0 + t * (g1 - g0);
  }
  const float length = std::sqrt(Dot(normal, normal));
  if (length > 1e-20f) {
    const float outward = -1.0f / length;
    for (float& value : normal) value *= outward;
  } else {
    // A flat field: the edge itself points from its inside end to its outside end.
    normal = {0.0f, 0.0f, 0.0f};
    normal[axis] = d[node] >= iso ? 1.0f : -1.0f;
  }
  std::copy(normal.begin(), normal.end(), &mesh->normals[3 * static_cast<std::size_t>(id)]);
  // Density equals iso at the vertex, so the flesh share is the flesh density over iso.
  mesh->flesh[id] =
      flesh ? std::clamp((flesh[node] + t * (flesh[other] - flesh[node])) / iso, 0.0f, 1.0f) : 0.0f;
}

CubeCases BuildCubeCases() {
  CubeCases cases;
  for (int mask = 0; mask < 256; ++mask) {
    std::vector<std::array<int, 3>> triangles;
    for (const std::vector<int>& loop : SurfaceLoops(mask)) {
      if (!Triangulate(loop, &triangles)) {
        throw std::logic_error("marching cubes: no valid triangulation in case " +
                               std::to_string(mask));
      }
    }
    if (triangles.size() > CubeCases::kMaxTriangles) {
      throw std::logic_error("marching cubes: too many triangles in case " + std::to_string(mask));
    }
    cases.triangle_count[mask] = static_cast<std::uint8_t>(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      for (int v = 0; v < 3; ++v) {
        cases.triangle_edges[mask][3 * t + v] = static_cast<std::uint8_t>(triangles[t][v]);
      }
    }
  }
  return cases;
}

}  // namespace

std::array<int, 2> EdgeCorners(int edge) {
  const int axis = edge / 4, rest = edge % 4;
  const int low_axis = axis == 0 ? 1 : 0;   // the lower of the two other axes
  const int high_axis = axis == 2 ? 1 : 2;  // the higher one
  const int first = ((rest & 1) << low_axis) | (((rest >> 1) & 1) << high_axis);
  return {first, first | (1 << axis)};
}

const CubeCases& MarchingCubesCases() {
  static const CubeCases cases = BuildCubeCases();
  return cases;
}

void ExtractIsoSurface(const DensityGrid& density, float iso, const DensityGrid* flesh_density,
                       TriangleMesh* mesh, IsoSurfaceScratch* scratch, int threads) {
  const CubeCases& cases = MarchingCubesCases();
  const int nx = density.nodes[0], ny = density.nodes[1], nz = density.nodes[2];
  if (nx < 2 || ny < 2 || nz < 2) {
    *mesh = TriangleMesh{};
    return;
  }
  IsoSurfaceScratch local_scratch;
  if (!scratch) scratch = &local_scratch;
  const std::size_t node_count = density.node_count();
  const std::size_t sy = static_cast<std::size_t>(nx), sz = sy * ny;
  const float* d = density.values.data();
  const float* flesh = flesh_density ? flesh_density->values.data() : nullptr;
  // Row r = j + ny k holds the nodes (0 .. nx - 1, j, k), contiguous from node r * nx.
  const int rows = ny * nz;

  // Where a cube edge's vertex id sits in the id buffers of the cube's two node layers.
  std::array<int, 12> edge_layer, edge_slot;
  for (int e = 0; e < 12; ++e) {
    const int c = EdgeCorners(e)[0];
    edge_layer[e] = CornerBit(c, 2);
    edge_slot[e] = 3 * (CornerBit(c, 0) + nx * CornerBit(c, 1)) + e / 4;
  }

  // Sized, not cleared: every entry read below is written first.
  scratch->inside.resize(node_count);
  scratch->row_kinds.resize(rows);
  scratch->row_vertices.resize(rows + 1);
  scratch->row_triangles.resize(rows + 1);
  const int team = threads > 0 ? threads : omp_get_max_threads();
  if (scratch->layer_vertex_ids.size() < static_cast<std::size_t>(team)) {
    scratch->layer_vertex_ids.resize(team);
  }
  std::uint8_t* const inside = scratch->inside.data();
  std::uint8_t* const row_kinds = scratch->row_kinds.data();
  std::uint32_t* const row_vertices = scratch->row_vertices.data();
  std::uint32_t* const row_triangles = scratch->row_triangles.data();
  row_vertices[0] = row_triangles[0] = 0;
  // Rows r0 and r1 are all outside or all inside alike: no edge between them is crossed.
  const auto alike = [&](int r0, int r1) {
    return row_kinds[r0] == row_kinds[r1] && row_kinds[r0] != (kHasInside | kHasOutside);
  };
  // The cases of the cubes whose first node is in row r, for i in [0, nx - 1).
  const auto row_cases = [&](int r, std::uint8_t* masks) {
    const std::uint8_t* a = inside + r * sy;
    const std::uint8_t *b = a + sy, *c = a + sz, *e = a + sy + sz;
    int i = 0;
    // Eight cubes at a time: flags are 0 or 1, so shifts by < 8 stay within their byte.
    for (; i + 9 <= nx; i += 8) {
      const std::uint8_t* corner_rows[4] = {a + i, b + i, c + i, e + i};
      std::uint64_t mask = 0;
      for (int row = 0; row < 4; ++row) {
        std::uint64_t first, second;
        std::memcpy(&first, corner_rows[row], 8);
        std::memcpy(&second, corner_rows[row] + 1, 8);
        mask |= first << (2 * row) | second << (2 * row + 1);
      }
      std::memcpy(masks + i, &mask, 8);
    }
    for (; i + 1 < nx; ++i) {
      masks[i] = static_cast<std::uint8_t>(a[i] | a[i + 1] << 1 | b[i] << 2 | b[i + 1] << 3 |
                                           c[i] << 4 | c[i + 1] << 5 | e[i] << 6 | e[i + 1] << 7);
    }
  };
  // Calls visit(i, axis) for each crossed edge row r owns (+x, +y, +z from node i), in one order.
  const auto for_each_crossing = [&](int r, auto&& visit) {
    const int j = r % ny, k = r / ny;
    const std::uint8_t* a = inside + r * sy;
    if (!alike(r, r)) ForEachDifference(a, a + 1, nx - 1, [&](int i) { visit(i, 0); });
    if (j + 1 < ny && !alike(r, r + 1))
      ForEachDifference(a, a + sy, nx, [&](int i) { visit(i, 1); });
    if (k + 1 < nz && !alike(r, r + ny))
      ForEachDifference(a, a + sz, nx, [&](int i) { visit(i, 2); });
  };

#pragma omp parallel if (node_count >= kParallelNodes) num_threads(team)
  {
    std::vector<std::uint8_t> masks(nx);

    // Inside flags, and which kinds of node each row holds (most rows are all one kind).
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const float* values = d + r * sy;
      std::uint8_t* flags = inside + r * sy;
      std::uint8_t any_inside = 0, all_inside = 1;
      for (int i = 0; i < nx; ++i) {
        const std::uint8_t in = values[i] >= iso;
        flags[i] = in;
        any_inside |= in;
        all_inside &= in;
      }
      row_kinds[r] = (any_inside ? kHasInside : 0) | (all_inside ? 0 : kHasOutside);
    }

    // Per row: the crossed edges its nodes own and the triangles of its cubes.
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const int j = r % ny, k = r / ny;
      const std::uint8_t* a = inside + r * sy;
      std::uint32_t vertices = 0, triangles = 0;
      if (!alike(r, r)) vertices += CountDifferences(a, a + 1, nx - 1);
      if (j + 1 < ny && !alike(r, r + 1)) vertices += CountDifferences(a, a + sy, nx);
      if (k + 1 < nz && !alike(r, r + ny)) vertices += CountDifferences(a, a + sz, nx);
      if (j + 1 < ny && k + 1 < nz &&
          !(alike(r, r + 1) && alike(r, r + ny) && alike(r, r + ny + 1))) {
        row_cases(r, masks.data());
        for (int i = 0; i + 1 < nx; ++i) {
          if (masks[i] != 0 && masks[i] != 255) triangles += cases.triangle_count[masks[i]];
        }
      }
      row_vertices[r + 1] = vertices;
      row_triangles[r + 1] = triangles;
    }

#pragma omp single
    {
      for (int r = 0; r < rows; ++r) {
        row_vertices[r + 1] += row_vertices[r];
        row_triangles[r + 1] += row_triangles[r];
      }
      // Resized, not cleared: every entry is written below, and the memory is reused.
      mesh->positions_m.resize(3 * static_cast<std::size_t>(row_vertices[rows]));
      mesh->normals.resize(3 * static_cast<std::size_t>(row_vertices[rows]));
      mesh->flesh.resize(row_vertices[rows]);
      mesh->indices.resize(3 * static_cast<std::size_t>(row_triangles[rows]));
    }

    // Vertices and triangles, one run of node layers per thread, moving up through z with the
    // vertex ids of two node layers at hand (small enough to stay in cache).
    const int threads = omp_get_num_threads(), thread = omp_get_thread_num();
    const int k_begin = nz * thread / threads, k_end = nz * (thread + 1) / threads;
    // Vertex ids of the crossed edges of node layers k (even k) and k + 1 (odd), in one buffer.
    std::vector<std::uint32_t>& layer_ids = scratch->layer_vertex_ids[thread];
    const std::size_t layer_size = 3 * sy * ny;
    // Numbers the vertices of node layer k (and computes them when this thread owns the layer).
    const auto number_layer = [&](int k, bool compute) {
      std::uint32_t* ids = layer_ids.data() + (k & 1) * layer_size;
      for (int j = 0; j < ny; ++j) {
        const int r = j + ny * k;
        std::uint32_t id = row_vertices[r];
        if (row_vertices[r + 1] == id) continue;
        for_each_crossing(r, [&](int i, int axis) {
          ids[3 * (i + nx * j) + axis] = id;
          if (compute) {
            AddVertex(density, flesh, iso, {i, j, k}, axis, id, mesh);
          }
          ++id;
        });
      }
    };
    if (k_begin < k_end) {
      layer_ids.resize(2 * layer_size);
      number_layer(k_begin, true);
    }
    for (int k = k_begin; k < k_end && k + 1 < nz; ++k) {
      number_layer(k + 1, k + 1 < k_end);
      const std::uint32_t* ids[2] = {layer_ids.data() + (k & 1) * layer_size,
                                     layer_ids.data() + ((k + 1) & 1) * layer_size};
      for (int j = 0; j + 1 < ny; ++j) {
        const int r = j + ny * k;
        if (row_triangles[r + 1] == row_triangles[r]) continue;
        row_cases(r, masks.data());
        std::uint32_t* out = &mesh->indices[3 * static_cast<std::size_t>(row_triangles[r])];
        for (int i = 0; i + 1 < nx;) {
          // Skip eight cubes at a time while they are all outside or all inside.
          std::uint64_t word = 1;
          if (i + 9 <= nx) std::memcpy(&word, &masks[i], 8);
          if (word == 0 || word == ~std::uint64_t{0}) {
            i += 8;
            continue;
          }
          const int mask = masks[i];
          const std::uint8_t* edges = cases.triangle_edges[mask].data();
          const int slot = 3 * (i + nx * j);
          for (int v = 0; v < 3 * cases.triangle_count[mask]; ++v) {
            *out++ = ids[edge_layer[edges[v]]][slot + edge_slot[edges[v]]];
          }
          ++i;
        }
      }
    }
  }
}

}  // namespace culinarycut::render
