// Setup, part 2: the two-sided blade (CPIC). Grid nodes the edge has passed are split into one
// layer per blade side, and the particles near the blade carry the side they are on.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/mpm/kernels/solver_internals.h"

namespace culinarycut::mpm {
namespace {

// A particle this close ahead of the edge (in dx) counts as parted: it shares the edge's cell.
constexpr double kRecordAheadOfEdgeCells = 0.5;

// Whether the grid node at global index `node` is split by side: close to the blade's mid-plane,
// within its length, and at least half a cell above the edge.
bool IsSplitNode(const KnifeSdf& knife, const SubstepContext& context, const Eigen::Vector3i& node) {
  const double dx = context.dx_m;
  const Eigen::Vector3d local =
      knife.ToTcpFrame(Eigen::Vector3d(node.x() * dx, node.y() * dx, node.z() * dx));
  const double height_m = -local.z();
  return std::abs(local.y()) < context.split_half_width_m &&
         std::abs(local.x()) <= context.half_length_m && height_m >= kSplitAboveEdgeCells * dx &&
         height_m <= context.blade_height_m + 0.5 * dx;
}

// The global node box that may hold split nodes (inclusive; empty when low > high).
void SplitRegion(const KnifeSdf& knife, const SubstepContext& context, Eigen::Vector3i* low,
                 Eigen::Vector3i* high) {
  const double dx = context.dx_m;
  const Eigen::AlignedBox3d region = knife.BladeBounds(context.split_half_width_m + dx);
  for (int axis = 0; axis < 3; ++axis) {
    (*low)[axis] = static_cast<int>(std::floor(region.min()[axis] / dx));
    (*high)[axis] = static_cast<int>(std::ceil(region.max()[axis] / dx));
  }
}

}  // namespace

// Runs on one thread while the others scan the particles: the split nodes within last substep's
// grid box grown by a cell (the box moves little), in global indices and lexicographic order.
template <typename Real>
void Solver<Real>::FindSplitCandidates(const SubstepContext& context) {
  Workspace& work = *workspace_;
  const Grid& grid = *grid_;
  work.split_candidates.clear();
  work.candidate_low = Eigen::Vector3i::Zero();
  work.candidate_high = -Eigen::Vector3i::Ones();
  if (!context.split_on || grid.size() == 0) return;
  Eigen::Vector3i low, high;
  SplitRegion(*knife_, context, &low, &high);
  // Grown by one cell each side: std::max / min in int64 so that no index overflows.
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = std::max(low[axis], grid.origin[axis] - 1);
    high[axis] = static_cast<int>(std::min<std::int64_t>(
        high[axis], std::int64_t(grid.origin[axis]) + grid.dims[axis]));
  }
  work.candidate_low = low;
  work.candidate_high = high;
  for (int i = low.x(); i <= high.x(); ++i) {
    for (int j = low.y(); j <= high.y(); ++j) {
      for (int k = low.z(); k <= high.z(); ++k) {
        const Eigen::Vector3i node(i, j, k);
        if (IsSplitNode(*knife_, context, node)) work.split_candidates.push_back(node);
      }
    }
  }
}

template <typename Real>
void Solver<Real>::SplitNodesNearBlade(const SubstepContext& context) {
  Grid& grid = *grid_;
  Workspace& work = *workspace_;
  grid.split_slot.assign(context.split_on ? grid.size() : 0, -1);
  grid.split_nodes.clear();
  if (context.split_on) {
    // The nodes of this substep's grid box that may be split (global indices, inclusive).
    Eigen::Vector3i low, high;
    SplitRegion(*knife_, context, &low, &high);
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = std::max(low[axis], grid.origin[axis]);
      high[axis] = std::min(high[axis], grid.origin[axis] + grid.dims[axis] - 1);
    }
    auto add = [&](const Eigen::Vector3i& node) {
      const Eigen::Vector3i local = node - grid.origin;
      const std::size_t index = grid.Index(local.x(), local.y(), local.z());
      grid.split_slot[index] = static_cast<std::int32_t>(grid.split_nodes.size());
      grid.split_nodes.push_back(index);
    };
    const bool empty = (low.array() > high.array()).any();
    const bool covered = (work.candidate_low.array() <= low.array()).all() &&
                         (high.array() <= work.candidate_high.array()).all();
    if (empty) {
      // No node of the box is near the blade.
    } else if (covered) {
      // The candidates in lexicographic order, restricted to the box: the same slots as a search.
      for (const Eigen::Vector3i& node : work.split_candidates) {
        if ((node.array() >= low.array()).all() && (node.array() <= high.array()).all()) add(node);
      }
    } else {
      for (int i = low.x(); i <= high.x(); ++i) {
        for (int j = low.y(); j <= high.y(); ++j) {
          for (int k = low.z(); k <= high.z(); ++k) {
            const Eigen::Vector3i node(i, j, k);
            if (IsSplitNode(*knife_, context, node)) add(node);
          }
        }
      }
    }
  }
  for (int side = 0; side < 2; ++side) {
    grid.layer[side].assign(grid.split_nodes.size(), GridNode<Real>::Zero());
  }
  MarkBlocksNearSplit(grid.split_nodes, grid.dims, &work.blocks);
}

template <typename Real>
CutCounts Solver<Real>::LabelBladeSides(const SubstepContext& context, std::size_t begin,
                                        std::size_t end) {
  Particles<Real>& p = particles_;
  CutCounts counts;
  if (!context.split_on) {
    std::fill(p.blade_side.begin() + begin, p.blade_side.begin() + end, std::int8_t(0));
    return counts;
  }
  const double dx = context.dx_m;
  const double reach = context.stencil_reach_m;
  const int cut = context.cut_index;
  const bool record_cuts = config().effects.damage;  // fracture off: the food heals behind the blade
  // A particle near the blade takes the side it is on, and keeps it once the edge has passed it
  // (from then on the blade stands between the sides); labels are dropped once it is clear of
  // the blade, so the next cut labels afresh. "Near": within a stencil's reach of a split node.
  // Once the edge is below it, the particle also records that side for this cut, for good.
  const Eigen::AlignedBox3d label_region =
      knife_->BladeBounds(context.split_half_width_m + reach + dx);
  for (std::size_t q = begin; q < end; ++q) {
    const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
    if (!label_region.contains(x)) {
      p.blade_side[q] = static_cast<std::int8_t>(BladeSide::kUnassigned);
      continue;
    }
    const Eigen::Vector3d local = knife_->ToTcpFrame(x);
    const double side_m = local.y();
    const double height_m = -local.z();
    const bool near = std::abs(local.x()) <= context.half_length_m + reach &&
                      height_m >= kSplitAboveEdgeCells * dx - reach &&
                      height_m <= context.blade_height_m + 0.5 * dx + reach &&
                      std::abs(side_m) < context.split_half_width_m + reach;
    if (!near) {
      p.blade_side[q] = static_cast<std::int8_t>(BladeSide::kUnassigned);
      continue;
    }
    if (p.blade_side[q] == static_cast<std::int8_t>(BladeSide::kUnassigned) || height_m < 0.0) {
      p.blade_side[q] = static_cast<std::int8_t>(side_m >= 0.0 ? BladeSide::kPositive
                                                               : BladeSide::kNegative);
    }
    ++counts.labelled;
    // Within the blade's length and the split width, with the edge below it or within the half
    // cell ahead of it that the edge nodes hold (food pressed into the board is parted too).
    if (record_cuts && height_m > -kRecordAheadOfEdgeCells * dx && std::abs(local.x()) <= context.half_length_m &&
        std::abs(side_m) < context.split_half_width_m) {
      p.cut_sides[q] = RecordCut(p.cut_sides[q], cut, p.blade_side[q] > 0);
      ++counts.recorded;
    }
  }
  return counts;
}

template void Solver<float>::FindSplitCandidates(const SubstepContext&);
template void Solver<double>::FindSplitCandidates(const SubstepContext&);
template void Solver<float>::SplitNodesNearBlade(const SubstepContext&);
template void Solver<double>::SplitNodesNearBlade(const SubstepContext&);
template CutCounts Solver<float>::LabelBladeSides(const SubstepContext&, std::size_t, std::size_t);
template CutCounts Solver<double>::LabelBladeSides(const SubstepContext&, std::size_t, std::size_t);

}  // namespace culinarycut::mpm
