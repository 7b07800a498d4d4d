#include "sim/render/density_grid.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace culinarycut::render {
namespace {

// Empty node layers around the particles' box: 1.5 cells of kernel reach + half a cell of slack.
constexpr double kMarginCells = 2.0;
// Slabs per grid along the splat axis: enough for threads to balance, few enough to be cheap.
constexpr int kTargetSlabs = 32;
constexpr int kMaxSlabs = kTargetSlabs;  // width >= ceil(nodes / kTargetSlabs) keeps slabs <= this
// Below this many particles threads cost more than they save.
constexpr std::size_t kParallelParticles = 16384;

// Four floats or ints at once (GCC/Clang vector extension): four particles' stencils, or the four
// x-neighbour nodes of one stencil row (the fourth weight zero).
typedef float Lanes __attribute__((vector_size(16)));
typedef std::int32_t IntLanes __attribute__((vector_size(16)));

// Quadratic B-spline stencils of four particles along one axis: first nodes and three weights.
struct AxisStencils {
  IntLanes base;
  Lanes w[3];
};

// `g`: positions along the axis in cells from the grid origin. The stencils always lie within
// base .. base + 3 <= nodes - 1 (the fourth node for the x lanes), whatever the input.
inline AxisStencils StencilsAt(Lanes g, int nodes) {
  const Lanes zero = {0.0f, 0.0f, 0.0f, 0.0f};
  const Lanes top = zero + static_cast<float>(nodes - 4);
  // g - 1/2 >= 0 inside the margin, so truncation is floor; clamping keeps absurd inputs (NaN
  // included: it fails every comparison) in bounds.
  Lanes shifted = g - 0.5f;
  shifted = shifted > zero ? shifted : zero;
  shifted = shifted < top ? shifted : top;
  AxisStencils s;
  s.base = __builtin_convertvector(shifted, IntLanes);
  const Lanes f = shifted - __builtin_convertvector(s.base, Lanes) + 0.5f;  // in [0.5, 1.5)
  s.w[0] = 0.5f * (1.5f - f) * (1.5f - f);
  s.w[1] = 0.75f - (f - 1.0f) * (f - 1.0f);
  s.w[2] = 0.5f * (f - 0.5f) * (f - 0.5f);
  return s;
}

}  // namespace

DensityGrid DensityGridAround(const std::array<float, 3>& lower_m,
                              const std::array<float, 3>& upper_m, float cell_size_m,
                              double* node_count_estimate) {
  DensityGrid grid;
  grid.cell_size_m = cell_size_m;
  double count = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    // Lattice indices in double: positions far from the origin must not overflow an int.
    const double first = std::floor(lower_m[axis] / cell_size_m) - kMarginCells;
    const double last = std::ceil(upper_m[axis] / cell_size_m) + kMarginCells;
    const double nodes = last - first + 1.0;
    count *= nodes;
    grid.origin_m[axis] = static_cast<float>(first * cell_size_m);
    grid.nodes[axis] = nodes < 2e9 ? static_cast<int>(nodes) : 0;
  }
  *node_count_estimate = count;
  return grid;
}

void SplatParticles(const ParticleView& particles, const std::uint32_t* indices, std::size_t count,
                    float weight, DensityGrid* grid, SplatScratch* scratch, int threads) {
  if (count == 0) return;
  if (*std::min_element(grid->nodes.begin(), grid->nodes.end()) < 4) {
    throw std::invalid_argument("SplatParticles: a grid needs at least 4 nodes per axis");
  }
  SplatScratch local_scratch;
  if (!scratch) scratch = &local_scratch;
  const float inverse_cell = 1.0f / grid->cell_size_m;
  const std::array<int, 3> n = grid->nodes;
  const std::array<const float*, 3> x = {particles.x_m, particles.y_m, particles.z_m};

  // Slabs of `width` >= 3 nodes along the longest axis: a particle whose stencil starts in slab s
  // writes only slabs s and s + 1 (its fourth x lane included), so slabs two apart never touch the
  // same node and a node hears from two slabs at most: the even one first, then the odd one.
  const int axis = static_cast<int>(std::max_element(n.begin(), n.end()) - n.begin());
  const int width = std::max(3, (n[axis] + kTargetSlabs - 1) / kTargetSlabs);
  const int slabs = (n[axis] + width - 1) / width;
  // A table, not a division per particle: integer division is slow.
  std::vector<std::uint8_t>& slab_of_base = scratch->slab_of_base;
  slab_of_base.resize(n[axis]);
  for (int base = 0; base < n[axis]; ++base) {
    slab_of_base[base] = static_cast<std::uint8_t>(base / width);
  }

  // Stable counting sort of the particles by slab, gathering their positions in cells from the
  // grid origin: each slab then sums in list order and the splat streams through memory.
  std::vector<std::uint8_t>& slab_of = scratch->slab_of;
  slab_of.resize(count);
  for (std::vector<float>& cells : scratch->cells) cells.resize(count + 3);  // + 3: whole lanes
  std::array<std::uint32_t, kMaxSlabs + 1> slab_start{};
  for (std::size_t s = 0; s < count; ++s) {
    const std::size_t p = indices ? indices[s] : s;
    // The same base as StencilsAt computes (same float operations), so the same slab.
    float shifted = (x[axis][p] - grid->origin_m[axis]) * inverse_cell - 0.5f;
    shifted = shifted > 0.0f ? shifted : 0.0f;
    shifted = shifted < static_cast<float>(n[axis] - 4) ? shifted : static_cast<float>(n[axis] - 4);
    slab_of[s] = slab_of_base[static_cast<int>(shifted)];
    ++slab_start[slab_of[s] + 1];
  }
  for (int slab = 0; slab < slabs; ++slab) slab_start[slab + 1] += slab_start[slab];
  {
    std::array<std::uint32_t, kMaxSlabs> fill;
    std::copy(slab_start.begin(), slab_start.begin() + slabs, fill.begin());
    for (std::size_t s = 0; s < count; ++s) {
      const std::size_t p = indices ? indices[s] : s;
      const std::uint32_t at = fill[slab_of[s]]++;
      for (int a = 0; a < 3; ++a)
        scratch->cells[a][at] = (x[a][p] - grid->origin_m[a]) * inverse_cell;
    }
  }

  float* values = grid->values.data();
  const std::size_t stride_y = static_cast<std::size_t>(n[0]);
  const std::size_t stride_z = stride_y * n[1];
  // Splats sorted particles s .. s + lanes - 1 of `slab`, their stencils computed four at a time.
  const auto splat_block = [&](std::uint32_t s, int lanes, int slab) {
    AxisStencils st[3];
    for (int a = 0; a < 3; ++a) {
      Lanes g;
      std::memcpy(&g, scratch->cells[a].data() + s, sizeof(g));
      st[a] = StencilsAt(g, n[a]);
    }
    // The sort computed the same bases; should a compiler fuse its float operations differently
    // and move one by a node, keeping the bases in the slab still makes a race impossible.
    const IntLanes lowest = IntLanes{} + slab * width;
    const IntLanes highest = IntLanes{} + std::min((slab + 1) * width - 1, n[axis] - 4);
    st[axis].base = st[axis].base < lowest ? lowest : st[axis].base;
    st[axis].base = st[axis].base > highest ? highest : st[axis].base;
    for (int l = 0; l < lanes; ++l) {
      // This lane's weights as scalars: 9 rows of 4 x-neighbours, each one multiply-add.
      const Lanes wx = {weight * st[0].w[0][l], weight * st[0].w[1][l], weight * st[0].w[2][l],
                        0.0f};
      const float wy[3] = {st[1].w[0][l], st[1].w[1][l], st[1].w[2][l]};
      const float wz[3] = {st[2].w[0][l], st[2].w[1][l], st[2].w[2][l]};
      float* corner = values + st[0].base[l] + stride_y * st[1].base[l] + stride_z * st[2].base[l];
      for (int dz = 0; dz < 3; ++dz) {
        float* plane = corner + stride_z * dz;
        for (int dy = 0; dy < 3; ++dy) {
          float* row = plane + stride_y * dy;
          Lanes sum;
          std::memcpy(&sum, row, sizeof(sum));
          sum += wx * (wy[dy] * wz[dz]);
          std::memcpy(row, &sum, sizeof(sum));
        }
      }
    }
  };

  // Even slabs, then odd slabs: within a phase no two slabs share a node, so threads need no
  // locks and every node sums in the same order whatever the thread count.
  const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel if (count >= kParallelParticles) num_threads(team)
  for (int parity = 0; parity < 2; ++parity) {
#pragma omp for schedule(dynamic, 1)
    for (int slab = parity; slab < slabs; slab += 2) {
      for (std::uint32_t s = slab_start[slab]; s < slab_start[slab + 1]; s += 4) {
        const int lanes = static_cast<int>(std::min<std::uint32_t>(4, slab_start[slab + 1] - s));
        splat_block(s, lanes, slab);
      }
    }
  }
}

}  // namespace culinarycut::render
