#include "sim/render/food_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "sim/render/density_grid.h"
#include "sim/render/marching_cubes.h"

namespace culinarycut::render {
namespace {

constexpr float kMinimumDefaultCellM = 0.001f;  // finer grids cost more than the eye gains

// The particles of one (object, piece): a range of the grouped index list and their bounds.
struct PieceParticles {
  std::uint64_t key = 0;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  std::array<float, 3> lower_m{};
  std::array<float, 3> upper_m{};
};

// Orders pieces by object, then piece label; negative labels count as piece 0.
std::uint64_t PieceKey(std::uint16_t object, std::int32_t piece) {
  return (static_cast<std::uint64_t>(object) << 32) |
         static_cast<std::uint32_t>(std::max<std::int32_t>(piece, 0));
}

void ValidateOptions(const FoodSurfaceOptions& options) {
  std::ostringstream message;
  if (!std::isfinite(options.cell_size_m) || options.cell_size_m < 0.0f) {
    message << "FoodSurfaceOptions::cell_size_m is " << options.cell_size_m
            << "; give a grid spacing in metres, or 0 to use the particle spacing";
  } else if (!(options.iso_level > 0.0f && options.iso_level < 1.0f)) {
    message << "FoodSurfaceOptions::iso_level is " << options.iso_level
            << "; it must lie in (0, 1), 0.5 puts the surface at the food's boundary";
  } else if (!std::isfinite(options.flesh_damage)) {
    message << "FoodSurfaceOptions::flesh_damage is " << options.flesh_damage
            << "; give a damage threshold in [0, 1]";
  } else if (options.max_grid_cells <= 0) {
    message << "FoodSurfaceOptions::max_grid_cells is " << options.max_grid_cells
            << "; it must be positive";
  } else if (options.max_threads < 0) {
    message << "FoodSurfaceOptions::max_threads is " << options.max_threads
            << "; give 0 (OpenMP's default) or a positive cap";
  } else {
    return;
  }
  throw std::invalid_argument("ExtractFoodSurfaces: " + message.str());
}

float CellSize(const ParticleView& particles, const FoodSurfaceOptions& options) {
  if (options.cell_size_m > 0.0f) return options.cell_size_m;
  if (!(particles.particle_spacing_m > 0.0f)) {
    std::ostringstream message;
    message << "ExtractFoodSurfaces: ParticleView::particle_spacing_m is "
            << particles.particle_spacing_m
            << "; set it to the solver's dx / ppc^(1/3) in metres, or set "
               "FoodSurfaceOptions::cell_size_m";
    throw std::invalid_argument(message.str());
  }
  return std::max(particles.particle_spacing_m, kMinimumDefaultCellM);
}

// Throws for the first particle with a non-finite position.
[[noreturn]] void ThrowNonFinite(const ParticleView& particles) {
  for (std::size_t p = 0; p < particles.count; ++p) {
    const float x[3] = {particles.x_m[p], particles.y_m[p], particles.z_m[p]};
    if (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2])) continue;
    std::ostringstream message;
    message << "ExtractFoodSurfaces: particle " << p << " has a non-finite position (" << x[0]
            << ", " << x[1] << ", " << x[2]
            << ") m; the simulation state is corrupt or the view points at the wrong arrays";
    throw std::invalid_argument(message.str());
  }
  throw std::logic_error("ExtractFoodSurfaces: no non-finite position found");
}

// Bounds of all particles (lower, upper), checking every position: plain loops that vectorise.
std::array<std::array<float, 3>, 2> CheckedBounds(const ParticleView& particles) {
  std::array<std::array<float, 3>, 2> bounds;
  std::uint32_t non_finite = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const float* x = axis == 0 ? particles.x_m : axis == 1 ? particles.y_m : particles.z_m;
    float lower = x[0], upper = x[0];
    for (std::size_t p = 0; p < particles.count; ++p) {
      lower = x[p] < lower ? x[p] : lower;
      upper = x[p] > upper ? x[p] : upper;
      std::uint32_t bits;
      std::memcpy(&bits, &x[p], sizeof(bits));
      non_finite |= (bits & 0x7f800000u) == 0x7f800000u;  // all exponent bits: inf or NaN
    }
    bounds[0][axis] = lower;
    bounds[1][axis] = upper;
  }
  if (non_finite) ThrowNonFinite(particles);
  return bounds;
}

// Whether every particle has the same (object, piece) key as the first.
bool OnePiece(const ParticleView& particles) {
  bool same = true;
  if (particles.object) {
    const std::uint16_t first = particles.object[0];
    for (std::size_t p = 0; p < particles.count; ++p) same &= particles.object[p] == first;
  }
  if (particles.piece) {
    const std::int32_t first = std::max<std::int32_t>(particles.piece[0], 0);
    for (std::size_t p = 0; p < particles.count; ++p) {
      same &= std::max<std::int32_t>(particles.piece[p], 0) == first;
    }
  }
  return same;
}

// Groups the particles by (object, piece) in ascending order, each group in ascending particle
// order, with each group's bounds: one pass, plus a counting sort into `grouped`. When all
// particles share one key, `grouped` stays empty: the group is all particles in order.
std::vector<PieceParticles> GroupByPiece(const ParticleView& particles,
                                         std::vector<std::uint32_t>* piece_of,
                                         std::vector<std::uint32_t>* grouped) {
  const std::size_t n = particles.count;
  const auto key_of = [&](std::size_t p) {
    return PieceKey(particles.object ? particles.object[p] : 0,
                    particles.piece ? particles.piece[p] : 0);
  };
  grouped->clear();
  if (OnePiece(particles)) {
    const std::array<std::array<float, 3>, 2> bounds = CheckedBounds(particles);
    PieceParticles piece;
    piece.key = key_of(0);
    piece.count = static_cast<std::uint32_t>(n);
    piece.lower_m = bounds[0];
    piece.upper_m = bounds[1];
    return {piece};
  }
  CheckedBounds(particles);

  std::vector<PieceParticles> pieces;  // in order of first appearance
  std::unordered_map<std::uint64_t, std::uint32_t> piece_of_key;
  piece_of->resize(n);
  // The current group's count and bounds live in registers until the key changes.
  std::uint64_t last_key = key_of(0);
  std::uint32_t current = 0, count = 0;
  std::array<float, 3> lower = {particles.x_m[0], particles.y_m[0], particles.z_m[0]};
  std::array<float, 3> upper = lower;
  pieces.push_back(PieceParticles{last_key, 0, 0, lower, upper});
  piece_of_key.emplace(last_key, 0);
  const auto flush = [&] {
    PieceParticles& piece = pieces[current];
    piece.count += count;
    for (int axis = 0; axis < 3; ++axis) {
      piece.lower_m[axis] = std::min(piece.lower_m[axis], lower[axis]);
      piece.upper_m[axis] = std::max(piece.upper_m[axis], upper[axis]);
    }
  };
  for (std::size_t p = 0; p < n; ++p) {
    const std::array<float, 3> x = {particles.x_m[p], particles.y_m[p], particles.z_m[p]};
    const std::uint64_t key = key_of(p);
    // Neighbours in memory mostly share a piece: look the key up only when it changes.
    if (key != last_key) {
      flush();
      const auto [it, added] = piece_of_key.emplace(key, static_cast<std::uint32_t>(pieces.size()));
      if (added) pieces.push_back(PieceParticles{key, 0, 0, x, x});
      current = it->second;
      last_key = key;
      count = 0;
      lower = upper = x;
    }
    (*piece_of)[p] = current;
    ++count;
    for (int axis = 0; axis < 3; ++axis) {
      lower[axis] = x[axis] < lower[axis] ? x[axis] : lower[axis];
      upper[axis] = x[axis] > upper[axis] ? x[axis] : upper[axis];
    }
  }
  flush();

  // Ascending keys; fill[first-appearance id] = where that group's next particle goes.
  std::vector<std::uint32_t> by_key(pieces.size());
  std::iota(by_key.begin(), by_key.end(), 0u);
  std::sort(by_key.begin(), by_key.end(),
            [&](std::uint32_t a, std::uint32_t b) { return pieces[a].key < pieces[b].key; });
  std::vector<PieceParticles> sorted(pieces.size());
  std::vector<std::uint32_t> fill(pieces.size());
  std::uint32_t first = 0;
  for (std::size_t rank = 0; rank < by_key.size(); ++rank) {
    sorted[rank] = pieces[by_key[rank]];
    sorted[rank].first = first;
    fill[by_key[rank]] = first;
    first += sorted[rank].count;
  }
  grouped->resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    (*grouped)[fill[(*piece_of)[p]]++] = static_cast<std::uint32_t>(p);
  }
  return sorted;
}

void ThrowGridTooLarge(const PieceParticles& piece, const DensityGrid& grid, double nodes,
                       const FoodSurfaceOptions& options) {
  std::ostringstream message;
  message << "ExtractFoodSurfaces: object " << (piece.key >> 32) << " piece "
          << (piece.key & 0xffffffffu) << " spans " << piece.upper_m[0] - piece.lower_m[0] << " x "
          << piece.upper_m[1] - piece.lower_m[1] << " x " << piece.upper_m[2] - piece.lower_m[2]
          << " m, which needs " << nodes << " density grid nodes at a cell size of "
          << grid.cell_size_m
          << " m, more than FoodSurfaceOptions::max_grid_cells = " << options.max_grid_cells
          << "; raise cell_size_m or max_grid_cells, or check for particles that flew away";
  throw std::invalid_argument(message.str());
}

}  // namespace

void ExtractFoodSurfaces(const ParticleView& particles, const FoodSurfaceOptions& options,
                         FoodSurfaceWorkspace* workspace, std::vector<FoodPieceSurface>* surfaces) {
  ValidateOptions(options);
  if (particles.count == 0) {
    surfaces->clear();
    return;
  }
  if (!particles.x_m || !particles.y_m || !particles.z_m) {
    throw std::invalid_argument(
        "ExtractFoodSurfaces: ParticleView has count > 0 but a null x_m, y_m or z_m");
  }
  if (particles.count > std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument("ExtractFoodSurfaces: more than 2^32 - 1 particles");
  }
  if (std::isnan(particles.particle_spacing_m) || std::isinf(particles.particle_spacing_m)) {
    throw std::invalid_argument(
        "ExtractFoodSurfaces: ParticleView::particle_spacing_m is not finite; set it to the "
        "solver's dx / ppc^(1/3) in metres");
  }
  const float cell_m = CellSize(particles, options);
  // Each particle fills spacing^3; with no spacing given, assume one particle per cell.
  const float spacing_m =
      particles.particle_spacing_m > 0.0f ? particles.particle_spacing_m : cell_m;
  const float weight = std::pow(spacing_m / cell_m, 3.0f);

  FoodSurfaceWorkspace& work = *workspace;
  const std::vector<PieceParticles> pieces = GroupByPiece(particles, &work.piece_of, &work.grouped);

  // Lay out every grid first, so an oversized piece fails before any work is done.
  std::vector<DensityGrid> layouts(pieces.size());
  for (std::size_t g = 0; g < pieces.size(); ++g) {
    double nodes = 0.0;
    layouts[g] = DensityGridAround(pieces[g].lower_m, pieces[g].upper_m, cell_m, &nodes);
    if (nodes > static_cast<double>(options.max_grid_cells)) {
      ThrowGridTooLarge(pieces[g], layouts[g], nodes, options);
    }
  }

  surfaces->resize(pieces.size());
  for (std::size_t g = 0; g < pieces.size(); ++g) {
    const PieceParticles& piece = pieces[g];
    const std::uint32_t* indices =
        work.grouped.empty() ? nullptr : work.grouped.data() + piece.first;
    FoodPieceSurface& surface = (*surfaces)[g];
    surface.object = static_cast<std::uint16_t>(piece.key >> 32);
    surface.piece = static_cast<std::int32_t>(piece.key & 0xffffffffu);
    surface.particle_count = piece.count;

    // The workspace's grids take this piece's layout and keep their memory.
    const auto lay_out = [&](DensityGrid* grid) {
      grid->origin_m = layouts[g].origin_m;
      grid->cell_size_m = layouts[g].cell_size_m;
      grid->nodes = layouts[g].nodes;
      grid->values.assign(grid->node_count(), 0.0f);
    };
    lay_out(&work.density);
    SplatParticles(particles, indices, piece.count, weight, &work.density, &work.splat,
                   options.max_threads);

    // Flesh: the same splat over the damaged particles only (usually few, often none).
    work.damaged.clear();
    if (particles.damage) {
      for (std::uint32_t s = 0; s < piece.count; ++s) {
        const std::uint32_t p = indices ? indices[s] : s;
        if (particles.damage[p] > options.flesh_damage) work.damaged.push_back(p);
      }
    }
    if (!work.damaged.empty()) {
      lay_out(&work.flesh_density);
      SplatParticles(particles, work.damaged.data(), work.damaged.size(), weight,
                     &work.flesh_density, &work.splat, options.max_threads);
    }
    ExtractIsoSurface(work.density, options.iso_level,
                      work.damaged.empty() ? nullptr : &work.flesh_density, &surface.mesh,
                      &work.iso_surface, options.max_threads);
  }
}

std::vector<FoodPieceSurface> ExtractFoodSurfaces(const ParticleView& particles,
                                                  const FoodSurfaceOptions& options) {
  FoodSurfaceWorkspace workspace;
  std::vector<FoodPieceSurface> surfaces;
  ExtractFoodSurfaces(particles, options, &workspace, &surfaces);
  return surfaces;
}

}  // namespace culinarycut::render
