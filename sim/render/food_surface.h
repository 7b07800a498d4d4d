// Food surfaces from particles: one closed triangle mesh per (object, piece), extracted by
// splatting the particles onto a density grid and running marching cubes on it, with a per-vertex
// flesh weight (skin where the surface is the food's original outside, flesh where damage or a
// cut has exposed the inside). See docs/food_surface.md.
//
// Each mesh (world frame, m) is welded (one vertex per crossed grid edge), closed (every edge is
// shared by exactly two triangles), counter-clockwise seen from outside, with unit outward
// normals from the density gradient (smooth shading). The surface sits about half a particle
// spacing outside the outermost particles: where the food's true boundary is.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/render/density_grid.h"
#include "sim/render/marching_cubes.h"
#include "sim/render/particle_view.h"
#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

struct FoodSurfaceOptions {
  // Density grid spacing (m); 0 means max(particle_spacing_m, 1 mm). Finer than the particle
  // spacing shows single particles as bumps; coarser is faster and smoother.
  float cell_size_m = 0.0f;
  float iso_level = 0.5f;      // in (0, 1): fraction of the density of a filled interior
  float flesh_damage = 0.05f;  // a particle with damage above this shows flesh
  // Most density grid nodes one piece may use; beyond it std::invalid_argument, instead of
  // exhausting memory (e.g. a particle that flew away stretches its piece's box).
  int max_grid_cells = 8'000'000;
  // > 0 caps the OpenMP threads (1: none); 0 uses OpenMP's default. The result is the same bits
  // either way. Use 1 when extraction runs beside other busy threads on few cores: its barriers
  // then wait for descheduled threads (docs/food_surface.md, Speed).
  int max_threads = 0;
};

struct FoodPieceSurface {
  std::uint16_t object = 0;  // food object index
  std::int32_t piece = 0;    // piece label, as in ParticleView::piece (negative -> 0)
  std::size_t particle_count = 0;
  // May be empty for a crumb of a few particles (always for one: it cannot fill a cell).
  // flesh per vertex: the share of the density there that comes from damaged particles
  // (damage > flesh_damage), in [0, 1]; 0 on the original skin, about 1 on a cut face.
  TriangleMesh mesh;
};

// One surface per (object, piece) that has particles, in ascending (object, piece) order.
// Particles may come in any order. Deterministic: the same input gives the same bits, whatever
// the thread count. Throws std::invalid_argument for a non-finite position, a null position array,
// no particle spacing and no cell size, a piece needing more than max_grid_cells nodes, or bad
// options. Empty input gives an empty result.
std::vector<FoodPieceSurface> ExtractFoodSurfaces(const ParticleView& particles,
                                                  const FoodSurfaceOptions& options = {});

// Memory kept between calls of the overload below (scratch only, nothing to read).
struct FoodSurfaceWorkspace {
  DensityGrid density, flesh_density;
  SplatScratch splat;
  IsoSurfaceScratch iso_surface;
  std::vector<std::uint32_t> grouped, piece_of, damaged;
};

// The same, for every frame: reuses `workspace` and the memory of the meshes already in
// `surfaces`, which it overwrites with the result. Once sizes settle it makes no large allocation
// (no page faults, no zero-filling). One workspace per thread that extracts. On error `surfaces`
// is left as it was.
void ExtractFoodSurfaces(const ParticleView& particles, const FoodSurfaceOptions& options,
                         FoodSurfaceWorkspace* workspace, std::vector<FoodPieceSurface>* surfaces);

}  // namespace culinarycut::render
