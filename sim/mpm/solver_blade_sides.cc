// Setup, part 2: the two-sided blade (CPIC). Grid nodes the edge has passed are split into one
// layer per blade side, and the particles near the blade carry the side they are on.
#include <algorithm>
#include <cmath>

#include "sim/mpm/solver_internals.h"

namespace culinarycut::mpm {
namespace {

// Nodes split by side only once the edge is this far below them; the edge itself presses on
// unsplit nodes, which is where cutting resistance and damage come from.
constexpr double kSplitAboveEdgeCells = 0.5;

}  // namespace

template <typename Real>
void Solver<Real>::SplitNodesNearBlade(const SubstepContext& context) {
  Grid& grid = *grid_;
  grid.split_slot.assign(context.split_on ? grid.size() : 0, -1);
  grid.split_nodes.clear();
  if (!context.split_on) return;
  const double dx = context.dx_m;
  const Eigen::AlignedBox3d region = knife_->BladeBounds(context.split_half_width_m + dx);
  Eigen::Vector3i lo, hi;
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = std::max(0, static_cast<int>(std::floor(region.min()[axis] / dx)) - grid.origin[axis]);
    hi[axis] = std::min(grid.dims[axis] - 1,
                        static_cast<int>(std::ceil(region.max()[axis] / dx)) - grid.origin[axis]);
  }
  for (int i = lo.x(); i <= hi.x(); ++i) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int k = lo.z(); k <= hi.z(); ++k) {
        const Eigen::Vector3d local = knife_->ToTcpFrame(grid.Position(i, j, k, dx));
        const double height_m = -local.z();
        if (std::abs(local.y()) < context.split_half_width_m &&
            std::abs(local.x()) <= context.half_length_m && height_m >= kSplitAboveEdgeCells * dx &&
            height_m <= context.blade_height_m + 0.5 * dx) {
          const std::size_t index = grid.Index(i, j, k);
          grid.split_slot[index] = static_cast<std::int32_t>(grid.split_nodes.size());
          grid.split_nodes.push_back(index);
        }
      }
    }
  }
  for (int side = 0; side < 2; ++side) {
    grid.layer[side].assign(grid.split_nodes.size(), GridNode<Real>::Zero());
  }
}

template <typename Real>
void Solver<Real>::LabelBladeSides(const SubstepContext& context) {
  Particles<Real>& p = particles_;
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  if (!context.split_on) {
    std::fill(p.blade_side.begin(), p.blade_side.end(), std::int8_t(0));
    return;
  }
  const double dx = context.dx_m;
  const double reach = context.stencil_reach_m;
  // A particle near the blade takes the side it is on, and keeps it once the edge has passed it
  // (from then on the blade stands between the sides); labels are dropped once it is clear of
  // the blade, so the next cut labels afresh. "Near": within a stencil's reach of a split node.
  const Eigen::AlignedBox3d label_region =
      knife_->BladeBounds(context.split_half_width_m + reach + dx);
#pragma omp parallel for num_threads(config_.threads) schedule(static)
  for (std::int64_t q = 0; q < n; ++q) {
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
    } else if (p.blade_side[q] == static_cast<std::int8_t>(BladeSide::kUnassigned) ||
               height_m < 0.0) {
      p.blade_side[q] = static_cast<std::int8_t>(side_m >= 0.0 ? BladeSide::kPositive
                                                               : BladeSide::kNegative);
    }
  }
}

template void Solver<float>::SplitNodesNearBlade(const SubstepContext&);
template void Solver<double>::SplitNodesNearBlade(const SubstepContext&);
template void Solver<float>::LabelBladeSides(const SubstepContext&);
template void Solver<double>::LabelBladeSides(const SubstepContext&);

}  // namespace culinarycut::mpm
