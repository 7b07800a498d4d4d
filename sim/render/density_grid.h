// A density field of one food piece sampled on a small world-aligned grid: particles splatted onto
// its nodes with the quadratic B-spline kernel, ready for iso-surface extraction.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/render/particle_view.h"

namespace culinarycut::render {

// Node (i, j, k) sits at origin_m + cell_size_m * (i, j, k); values are stored x fastest.
struct DensityGrid {
  std::array<float, 3> origin_m{};  // world frame (m)
  float cell_size_m = 0.0f;         // node spacing (m)
  std::array<int, 3> nodes{};       // node count per axis
  std::vector<float> values;        // per node; dimensionless (1 = a fully filled cell)

  std::size_t node_count() const {
    return static_cast<std::size_t>(nodes[0]) * nodes[1] * nodes[2];
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(nodes[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(nodes[1]) * k);
  }
};

// Node lattice (no values yet) covering particles in [lower_m, upper_m] with a margin of two
// cells, so that every particle's kernel fits and the outermost node layer stays empty: an
// iso-surface extracted from the grid is then always closed. The origin lies on the world lattice
// of multiples of cell_size_m, so a piece that moves does not make its surface shimmer.
// `node_count_estimate` gets the node count in double, before any int could overflow.
DensityGrid DensityGridAround(const std::array<float, 3>& lower_m,
                              const std::array<float, 3>& upper_m, float cell_size_m,
                              double* node_count_estimate);

// Memory SplatParticles keeps between calls (overwritten each call).
struct SplatScratch {
  std::vector<std::uint8_t> slab_of_base;   // per node along the slab axis: its slab
  std::vector<std::uint8_t> slab_of;        // per listed particle: its slab
  std::array<std::vector<float>, 3> cells;  // positions in cells from the origin, sorted by slab
};

// Adds `weight` x N((x_p - x_node) / cell) for each listed particle (`indices`, or the first
// `count` particles when null) to every node of its 3 x 3 x 3 quadratic B-spline stencil. N
// integrates to one cell volume: with weight = particle volume / cell volume a filled interior
// reads 1 and a flat boundary half a particle spacing outside the outermost particles reads 0.5.
// `grid->values` must be sized and zeroed, with at least 4 nodes per axis (DensityGridAround
// gives 5 or more). Deterministic and independent of the thread count: slabs of nodes along the
// longest axis are splatted in two alternating phases, each slab in the listed particle order.
// `scratch` (optional) keeps memory for the next call; `threads` > 0 caps the OpenMP team.
void SplatParticles(const ParticleView& particles, const std::uint32_t* indices, std::size_t count,
                    float weight, DensityGrid* grid, SplatScratch* scratch = nullptr,
                    int threads = 0);

}  // namespace culinarycut::render
