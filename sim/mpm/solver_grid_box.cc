// Setup, part 1: the grid box around the particles (only the food's neighbourhood) and the
// particles' grouping into P2G blocks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/mpm/solver_internals.h"

namespace culinarycut::mpm {
namespace {

constexpr double kMaxCellIndex = 1 << 29;  // |x| / dx beyond this would overflow the cell ints
constexpr double kMaxGridNodes = 4e8;      // 6.4 GB of float nodes: a blow-up, not a scene
constexpr std::uint64_t kReorderEverySubsteps = 16;

}  // namespace

template <typename Real>
void Solver<Real>::FitGridBox() {
  const Particles<Real>& p = particles_;
  Grid& grid = *grid_;
  const std::size_t n = p.size();
  const double dx = config_.dx_m;
  const int threads = config_.threads;
  // Bounds per chunk in parallel (min and max do not depend on the order); a NaN fails the
  // comparisons below, which min/max alone would step over.
  const std::size_t bound_chunks = ChunkCount(n);
  std::vector<std::array<Real, 7>> chunk_bounds(bound_chunks);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(bound_chunks); ++c) {
    std::array<Real, 7> b = {std::numeric_limits<Real>::max(), std::numeric_limits<Real>::max(),
                             std::numeric_limits<Real>::max(), -std::numeric_limits<Real>::max(),
                             -std::numeric_limits<Real>::max(), -std::numeric_limits<Real>::max(),
                             Real(1)};
    const std::size_t end_q = std::min(n, (c + 1) * kChunk);
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t q = c * kChunk; q < end_q; ++q) {
        const Real x = p.position[axis][q];
        b[6] = (x >= -std::numeric_limits<Real>::max() && x <= std::numeric_limits<Real>::max()) ? b[6] : Real(0);
        b[axis] = std::min(b[axis], x);
        b[3 + axis] = std::max(b[3 + axis], x);
      }
    }
    chunk_bounds[c] = b;
  }
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  bool finite = true;
  for (const auto& b : chunk_bounds) {
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
  const int margin = config_.grid_margin_cells;
  for (int axis = 0; axis < 3; ++axis) {
    grid.origin[axis] = static_cast<int>(std::floor(low[axis] / dx)) - margin;
    grid.dims[axis] = static_cast<int>(std::floor(high[axis] / dx)) + margin + 3 - grid.origin[axis];
  }
  if (grid.dims.template cast<double>().prod() > kMaxGridNodes) {
    throw std::runtime_error(
        "MPM particles spread over " + std::to_string((high - low).maxCoeff()) +
        " m: the grid box would need " + std::to_string(grid.dims.template cast<double>().prod()) +
        " nodes (limit " + std::to_string(kMaxGridNodes) + "); the food has flown apart");
  }
  // Cleared serially: a memset, cheaper than waking the threads for it.
  grid.node.assign(grid.size(), GridNode<Real>::Zero());
}

template <typename Real>
void Solver<Real>::SortParticlesIntoBlocks(const SubstepContext& context) {
  ParticleBlocks& blocks = workspace_->blocks;
  const Grid& grid = *grid_;
  const int threads = config_.threads;
  SortIntoBlocks(particles_, Real(1.0 / context.dx_m), grid.origin, grid.dims, threads, &blocks);
  // Every few substeps, store the particles in block order, so the transfers stream through
  // memory instead of jumping (deterministic: the order depends only on the positions).
  if (workspace_->substeps_since_reorder++ % kReorderEverySubsteps == 0) {
    StoreInBlockOrder(threads, &blocks, &particles_, &workspace_->reorder_spare);
  }
  MarkBlocksNearSplit(grid.split_nodes, grid.dims, &blocks);
}

template void Solver<float>::FitGridBox();
template void Solver<double>::FitGridBox();
template void Solver<float>::SortParticlesIntoBlocks(const SubstepContext&);
template void Solver<double>::SortParticlesIntoBlocks(const SubstepContext&);

}  // namespace culinarycut::mpm
