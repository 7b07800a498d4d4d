// Setup, part 1: the scan of the particles (bounds, side labels, momentum), the grid box around
// them (only the food's neighbourhood) and the particles' grouping into P2G blocks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/mpm/kernels/solver_internals.h"

namespace culinarycut::mpm {
namespace {

constexpr double kMaxCellIndex = 1 << 29;  // |x| / dx beyond this would overflow the cell ints
constexpr double kMaxGridNodes = 4e8;      // 6.4 GB of float nodes: a blow-up, not a scene
constexpr std::uint64_t kReorderEverySubsteps = 16;

// Low and high bounds of particles [begin, end) per axis, and 1 if all positions are finite, 0
// if not. In 8 lanes, so it vectorises: min and max do not depend on the order; x - x is 0 for a
// finite x and NaN otherwise, so the lanes' sums say whether all were finite.
template <typename Real>
std::array<Real, 7> ChunkBounds(const Particles<Real>& p, std::size_t begin, std::size_t end) {
  constexpr int kLanes = 8;
  constexpr Real kMax = std::numeric_limits<Real>::max();
  std::array<Real, 7> bounds = {kMax, kMax, kMax, -kMax, -kMax, -kMax, Real(1)};
  Real finite_sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const Real* const x = p.position[axis].data();
    Real low[kLanes], high[kLanes], sum[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      low[l] = kMax;
      high[l] = -kMax;
      sum[l] = 0;
    }
    std::size_t q = begin;
    for (; q + kLanes <= end; q += kLanes) {
      for (int l = 0; l < kLanes; ++l) {
        const Real value = x[q + l];
        low[l] = value < low[l] ? value : low[l];
        high[l] = value > high[l] ? value : high[l];
        sum[l] += value - value;
      }
    }
    for (; q < end; ++q) {
      low[0] = x[q] < low[0] ? x[q] : low[0];
      high[0] = x[q] > high[0] ? x[q] : high[0];
      sum[0] += x[q] - x[q];
    }
    for (int l = 0; l < kLanes; ++l) {
      bounds[axis] = std::min(bounds[axis], low[l]);
      bounds[3 + axis] = std::max(bounds[3 + axis], high[l]);
      finite_sum += sum[l];
    }
  }
  bounds[6] = finite_sum == Real(0) ? Real(1) : Real(0);
  return bounds;
}

}  // namespace

template <typename Real>
void Solver<Real>::PrepareWorkspace(int team) {
  Workspace& work = *workspace_;
  const std::size_t n = active_count_;  // the frozen particles (stored last) are not integrated
  const std::size_t chunks = ChunkCount(n);
  work.chunk_bounds.resize(chunks);
  work.momentum_of_chunk.assign(chunks, Eigen::Vector3d::Zero());
  work.cut_counts_of_chunk.assign(chunks, CutCounts{});
  work.node_momentum.resize(n);
  work.elastic_energy_of_chunk.assign(chunks, 0.0);
  work.particle_chunks.assign(chunks, ParticleTotals{});
  work.chunk_done.resize(chunks, 0);
  work.blocks.block_of.resize(n);
  work.blocks.order.resize(n);
  work.blocks.thread_counts.resize(team);
  // Every few substeps, store the particles in block order, so the transfers stream through
  // memory instead of jumping (deterministic: the order depends only on the positions).
  work.reorder_now = work.substeps_since_reorder++ % kReorderEverySubsteps == 0;
  if (work.reorder_now) SizeBlockOrderSpares(&work.blocks, particles_, &work.reorder_spare);
  if (!work.contact_materials_ready) {
    work.contact_materials = ContactMaterials(materials(), config().cutting, config().mass_scaling);
    work.contact_materials_ready = true;
  }
  // Two cells of margin: a node touches the food's particles within its stencil's reach.
  work.contact_materials.Measure(particles_, 2.0 * config().dx_m);
  // A new stamp marks this substep's finished stress chunks and blocks (no clearing).
  if (++work.stamp == 0) {
    std::fill(work.chunk_done.begin(), work.chunk_done.end(), 0u);
    std::fill(work.block_done.begin(), work.block_done.end(), 0u);
    work.stamp = 1;
  }
}

template <typename Real>
void Solver<Real>::ScanParticles(const SubstepContext& context) {
  Particles<Real>& p = particles_;
  Workspace& work = *workspace_;
  const std::size_t n = active_count_;
  const bool sense_force = config().effects.force_sensing;
#pragma omp for schedule(dynamic, 1)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(ChunkCount(n)); ++c) {
    const std::size_t begin = c * kChunk;
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    work.chunk_bounds[c] = ChunkBounds(p, begin, end);
    work.cut_counts_of_chunk[c] = LabelBladeSides(context, begin, end);
    if (sense_force) {
      Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
      for (std::size_t q = begin; q < end; ++q) {
        for (int axis = 0; axis < 3; ++axis) momentum[axis] += double(p.mass[q]) * p.velocity[axis][q];
      }
      work.momentum_of_chunk[c] = momentum;
    }
  }
}

// Every thread computes the box from the chunks' bounds (the same bits on each): no single, no
// barrier. Throws (on every thread alike) for positions that are no number or too far out.
template <typename Real>
void Solver<Real>::FitGridBox(const SubstepContext& context, Eigen::Vector3i* origin_out,
                              Eigen::Vector3i* dims_out) const {
  const Workspace& work = *workspace_;
  const double dx = context.dx_m;
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  bool finite = true;
  for (const auto& b : work.chunk_bounds) {
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = std::min(low[axis], double(b[axis]));
      high[axis] = std::max(high[axis], double(b[3 + axis]));
    }
    finite = finite && b[6] > Real(0);
  }
  if (!finite) throw std::runtime_error("MPM particles left the finite range (NaN or Inf position)");
  // Cell indices must fit an int, and the grid box must fit in memory.
  if ((low.cwiseAbs().array() / dx > kMaxCellIndex).any() ||
      (high.cwiseAbs().array() / dx > kMaxCellIndex).any()) {
    throw std::runtime_error("MPM particles are too far from the origin for dx = " +
                             std::to_string(dx) + " m");
  }
  const int margin = config().grid_margin_cells;
  Eigen::Vector3i origin, dims;
  for (int axis = 0; axis < 3; ++axis) {
    origin[axis] = static_cast<int>(std::floor(low[axis] / dx)) - margin;
    dims[axis] = static_cast<int>(std::floor(high[axis] / dx)) + margin + 3 - origin[axis];
  }
  if (dims.template cast<double>().prod() > kMaxGridNodes) {
    throw std::runtime_error(
        "MPM particles spread over " + std::to_string((high - low).maxCoeff()) +
        " m: the grid box would need " + std::to_string(dims.template cast<double>().prod()) +
        " nodes (limit " + std::to_string(kMaxGridNodes) + "); the food has flown apart");
  }
  *origin_out = origin;
  *dims_out = dims;
}

// Team: the block sort around two serial jobs that run side by side (OpenMP sections): the grid
// box itself (cleared nodes, split nodes) and the blocks' offsets and colour lists.
template <typename Real>
void Solver<Real>::SortParticlesIntoBlocks(const SubstepContext& context,
                                           const Eigen::Vector3i& origin,
                                           const Eigen::Vector3i& dims, SubstepShared* shared) {
  Workspace& work = *workspace_;
  Grid& grid = *grid_;
  CountBlocks(particles_, active_count_, Real(1.0 / context.dx_m), origin, dims, &work.blocks);  // a barrier
  auto guarded = [shared](auto&& job) {
    try {
      job();
    } catch (...) {
#pragma omp critical(culinarycut_mpm_substep_error)
      {
        if (!shared->failed) shared->error = std::current_exception();
        shared->failed = true;
      }
    }
  };
#pragma omp sections
  {
#pragma omp section
    guarded([&] {
      grid.origin = origin;
      grid.dims = dims;
      // Cleared serially: a memset, beside the other section.
      grid.node.assign(grid.size(), GridNode<Real>::Zero());
      work.grid_chunks.assign(ChunkCount(grid.size()), GridTotals{});
      SplitNodesNearBlade(context);
    });
#pragma omp section
    guarded([&] {
      ListBlocks(dims, &work.blocks);
      work.block_done.resize(work.blocks.count(), 0);
      work.next_item.store(0, std::memory_order_relaxed);  // the sections' barrier publishes them
      work.sorted_threads.store(0, std::memory_order_relaxed);
    });
  }
  if (shared->failed) return;  // read by every thread after the sections' barrier
  // Without a reorder, nothing waits for the whole order but the scatter's blocks, which come
  // after the stress chunks in P2G's queue: no barrier here, they wait for sorted_threads.
  PlaceInBlocks(active_count_, &work.blocks, work.reorder_now ? nullptr : &work.sorted_threads);
  if (work.reorder_now) {
    StoreInBlockOrder(&work.blocks, &particles_, &work.reorder_spare);
    work.sorted_threads.fetch_add(1, std::memory_order_relaxed);  // after barriers: all see it
  }
}

template void Solver<float>::PrepareWorkspace(int);
template void Solver<double>::PrepareWorkspace(int);
template void Solver<float>::ScanParticles(const SubstepContext&);
template void Solver<double>::ScanParticles(const SubstepContext&);
template void Solver<float>::FitGridBox(const SubstepContext&, Eigen::Vector3i*,
                                       Eigen::Vector3i*) const;
template void Solver<double>::FitGridBox(const SubstepContext&, Eigen::Vector3i*,
                                        Eigen::Vector3i*) const;
template void Solver<float>::SortParticlesIntoBlocks(const SubstepContext&, const Eigen::Vector3i&,
                                                    const Eigen::Vector3i&, SubstepShared*);
template void Solver<double>::SortParticlesIntoBlocks(const SubstepContext&, const Eigen::Vector3i&,
                                                     const Eigen::Vector3i&, SubstepShared*);

}  // namespace culinarycut::mpm
