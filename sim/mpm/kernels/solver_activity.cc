// Activity: only the food near the blade, or moving, is integrated (SolverConfig::activity). A
// particle far from the blade that has stayed quiet for a few checks freezes: it keeps its place
// and deformation, and its mass and stress force go on acting on the grid as a fixed load, so the
// food beside it still leans on it. It wakes when the blade comes within the radius or a grid node
// it shares with moving food moves faster than the wake speed. Frozen particles are stored after
// the moving ones, so every stage of the substep runs over [0, active_count_) unchanged. The same
// freezing puts whole food objects to sleep (SetObjectAsleep: a scene's resting distractors) with the
// radius off.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/mpm/kernels/solver_internals.h"
#include "sim/mpm/kernels/transfer_stencil.h"

namespace culinarycut::mpm {
namespace {

// Index of node (i, j, k) of a box of `dims` nodes.
inline std::size_t BoxIndex(const Eigen::Vector3i& dims, int i, int j, int k) {
  return (static_cast<std::size_t>(i) * dims.y() + j) * dims.z() + k;
}

// Calls visit(load node index, grid node index) for every node the load's box and the grid box
// share.
template <typename Grid, typename Load, typename Visit>
void ForEachSharedNode(const Grid& grid, const Load& load, Visit&& visit) {
  const Eigen::Vector3i low = grid.origin.cwiseMax(load.origin);
  const Eigen::Vector3i high = (grid.origin + grid.dims).cwiseMin(load.origin + load.dims);
  for (int x = low.x(); x < high.x(); ++x) {
    for (int y = low.y(); y < high.y(); ++y) {
      for (int z = low.z(); z < high.z(); ++z) {
        visit(BoxIndex(load.dims, x - load.origin.x(), y - load.origin.y(), z - load.origin.z()),
              grid.Index(x - grid.origin.x(), y - grid.origin.y(), z - grid.origin.z()));
      }
    }
  }
}

// Substeps between activity checks: every few, sooner for a fast knife, which must not cross more than
// a cell between checks (the radius keeps 5 cells between the blade and frozen food).
std::uint64_t CheckInterval(const KnifeSdf& knife, const SubstepContext& context, int most) {
  const double knife_speed_m_s = knife.motion().linear_velocity_m_s.norm() +
                                 knife.motion().angular_velocity_rad_s.norm() *
                                     (0.5 * knife.geometry().blade_length_m + knife.geometry().blade_height_m);
  const double steps_per_cell = knife_speed_m_s > 0.0 ? context.dx_m / (knife_speed_m_s * context.dt_s) : 1e9;
  return static_cast<std::uint64_t>(std::clamp(std::floor(steps_per_cell), 1.0, double(most)));
}

}  // namespace

template <typename Real>
void Solver<Real>::UpdateActivity(const SubstepContext& context) {
  Particles<Real>& p = particles_;
  const std::size_t n = p.size();
  const Activity& activity = config().activity;
  FrozenLoad& frozen = *frozen_;
  const bool radius_on = activity.radius_m > 0.0;
  if (radius_on && !knife_) {
    active_count_ = n;  // no blade to measure the radius from: every particle moves
    frozen.valid = false;
    return;
  }
  if (p.activity.size() != n) p.activity.resize(n, 0);  // particles built field by field
  // The frozen particles must be the last ones; those woken after the last substep (pushed), a
  // restored snapshot's or new particles may break that.
  std::size_t first_frozen = n;
  for (std::size_t q = 0; q < n; ++q) {
    if (p.activity[q] == kFrozen) {
      first_frozen = q;
      break;
    }
  }
  if (!radius_on && first_frozen == n) {
    active_count_ = n;  // off and no object asleep (SetObjectAsleep): every particle moves
    frozen.valid = false;
    return;
  }
  bool partitioned = true;
  for (std::size_t q = first_frozen; q < n && partitioned; ++q) partitioned = p.activity[q] == kFrozen;

  // Radius off, only the objects put to sleep are frozen: nothing is checked, they wake when pushed.
  bool changed = !partitioned;
  const bool check = radius_on && workspace_->substeps_since_reorder %
                                          CheckInterval(*knife_, context, activity.check_every_substeps) == 0;
  if (check) {
    const KnifeSdf& knife = *knife_;
    const double dx = context.dx_m;
    const Real sleep_speed = Real(activity.sleep_speed_m_s);
    const Real sleep_speed_sq = sleep_speed * sleep_speed;
    const Real sleep_c = Real(activity.sleep_speed_m_s / dx);  // |C_ij| dx below the sleep speed
    const double sleep_radius_m = activity.radius_m + dx;      // hysteresis: a cell further out
    for (std::size_t q = 0; q < n; ++q) {
      const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
      std::uint8_t& state = p.activity[q];
      if (state == kFrozen) {
        if (knife.BoxDistance(x) < activity.radius_m) {
          state = 0;
          changed = true;
        }
        continue;
      }
      bool quiet = SquaredSpeed(p.velocity[0][q], p.velocity[1][q], p.velocity[2][q]) < sleep_speed_sq;
      for (int k = 0; k < 9 && quiet; ++k) quiet = std::abs(p.C[k][q]) < sleep_c;
      quiet = quiet && knife.BoxDistance(x) > sleep_radius_m;
      state = quiet ? static_cast<std::uint8_t>(state + 1) : std::uint8_t(0);
      if (state >= activity.quiet_checks) {
        // Frozen at rest: its velocity and affine field are dropped (below the sleep speed).
        state = kFrozen;
        for (int axis = 0; axis < 3; ++axis) p.velocity[axis][q] = Real(0);
        for (int k = 0; k < 9; ++k) p.C[k][q] = Real(0);
        changed = true;
      }
    }
  }
  if (changed) {
    // Stable partition, the moving particles first, by the block reorder's permutation.
    ParticleBlocks& blocks = workspace_->blocks;
    blocks.order.clear();
    for (std::size_t q = 0; q < n; ++q) {
      if (p.activity[q] != kFrozen) blocks.order.push_back(static_cast<std::uint32_t>(q));
    }
    active_count_ = blocks.order.size();
    for (std::size_t q = 0; q < n; ++q) {
      if (p.activity[q] == kFrozen) blocks.order.push_back(static_cast<std::uint32_t>(q));
    }
    blocks.block_of.resize(n);
    SizeBlockOrderSpares(&blocks, p, &workspace_->reorder_spare);
    StoreInBlockOrder(&blocks, &p, &workspace_->reorder_spare);  // one thread: no team here
    frozen.valid = false;
  } else {
    active_count_ = first_frozen;
  }
  if (!frozen.valid) BuildFrozenLoad(context);
}

template <typename Real>
void Solver<Real>::SetObjectAsleep(std::uint16_t object, bool asleep) {
  Particles<Real>& p = particles_;
  if (p.activity.size() != p.size()) p.activity.resize(p.size(), 0);
  for (std::size_t q = 0; q < p.size(); ++q) {
    if (p.object[q] != object || (p.activity[q] == kFrozen) == asleep) continue;
    p.activity[q] = asleep ? kFrozen : std::uint8_t(0);
    if (!asleep) continue;
    for (int axis = 0; axis < 3; ++axis) p.velocity[axis][q] = Real(0);
    for (int k = 0; k < 9; ++k) p.C[k][q] = Real(0);
  }
  // The next substep finds them out of order (or the frozen set changed): it repartitions and rebuilds the load.
  frozen_->valid = false;
}

// The frozen particles' mass and stress force on the nodes of their own box: P2G's stress pass at
// zero velocity and affine field over a unit step, whose momentum is then the force.
template <typename Real>
void Solver<Real>::BuildFrozenLoad(const SubstepContext& context) {
  Particles<Real>& p = particles_;
  FrozenLoad& frozen = *frozen_;
  Workspace& work = *workspace_;
  const std::size_t n = p.size();
  frozen.valid = true;
  frozen.elastic_energy_j = 0.0;
  frozen.node.clear();
  frozen.pushed.clear();
  frozen.dims = Eigen::Vector3i::Zero();
  if (active_count_ >= n) return;
  const Real inv_dx = Real(1.0 / context.dx_m);
  Eigen::Vector3i low = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i high = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  for (std::size_t q = active_count_; q < n; ++q) {
    for (int axis = 0; axis < 3; ++axis) {
      const int cell = CellOf(p.position[axis][q], inv_dx);
      low[axis] = std::min(low[axis], cell);
      high[axis] = std::max(high[axis], cell + 2);
    }
  }
  frozen.origin = low;
  frozen.dims = high - low + Eigen::Vector3i::Ones();
  const std::size_t nodes = static_cast<std::size_t>(frozen.dims.x()) * frozen.dims.y() * frozen.dims.z();
  frozen.node.assign(nodes, Vector4<Real>::Zero());
  frozen.pushed.assign(nodes, 0);
  work.node_momentum.resize(n);
  SubstepContext unit_step = context;
  unit_step.dt_s = 1.0;  // at rest the momentum over 1 s is the stress force itself (N)
  for (std::size_t begin = active_count_; begin < n; begin += kChunk) {
    frozen.elastic_energy_j += ComputeAffineMomentum(unit_step, begin, std::min(n, begin + kChunk), true);
  }
  const std::size_t stride_i = static_cast<std::size_t>(frozen.dims.y()) * frozen.dims.z();
  const std::size_t stride_j = static_cast<std::size_t>(frozen.dims.z());
  for (std::size_t q = active_count_; q < n; ++q) {
    Real position[3][1] = {{p.position[0][q]}, {p.position[1][q]}, {p.position[2][q]}};
    StencilLanes<Real, 1> stencil;
    StencilBatch<Real, 1>(position, inv_dx, frozen.origin, frozen.dims, &stencil);
    const NodeMomentum<Real>& values = work.node_momentum[q];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < 3; ++k) {
          const Real w = stencil.w[0][i][0] * stencil.w[1][j][0] * stencil.w[2][k][0];
          frozen.node[stencil.first_node[0] + i * stride_i + j * stride_j + k] +=
              w * (values.at_first_node + Real(i) * values.step[0] + Real(j) * values.step[1] +
                   Real(k) * values.step[2]);
        }
      }
    }
  }
}

template <typename Real>
void Solver<Real>::AddFrozenLoad(const SubstepContext& context) {
  const FrozenLoad& frozen = *frozen_;
  if (active_count_ >= particles_.size() || frozen.node.empty()) return;
  Grid& grid = *grid_;
  const Real dt = Real(context.dt_s);
  ForEachSharedNode(grid, frozen, [&](std::size_t load_index, std::size_t node) {
    const Vector4<Real>& load = frozen.node[load_index];
    if (load[3] <= Real(0)) return;
    // Split nodes lie within a few cells of the blade, where nothing is frozen (radius >= 5 dx).
    grid.node[node] += Vector4<Real>(dt * load[0], dt * load[1], dt * load[2], load[3]);
  });
}

template <typename Real>
void Solver<Real>::MarkPushedFrozenNodes() {
  FrozenLoad& frozen = *frozen_;
  if (active_count_ >= particles_.size() || frozen.node.empty()) return;
  const Grid& grid = *grid_;
  const Real wake_sq = Real(config().activity.wake_speed_m_s * config().activity.wake_speed_m_s);
  ForEachSharedNode(grid, frozen, [&](std::size_t load_index, std::size_t grid_index) {
    const Real frozen_mass = frozen.node[load_index][3];
    if (frozen_mass <= Real(0)) return;
    const GridNode<Real>& node = grid.node[grid_index];  // (velocity, mass)
    // Only nodes moving food shares: the frozen food's own nodes are never integrated.
    if (node[3] - frozen_mass <= Real(1e-3) * node[3]) return;
    if (node.template head<3>().squaredNorm() > wake_sq) {
      frozen.pushed[load_index] = 1;
      frozen.any_pushed = true;
    }
  });
}

// After the substep: frozen particles sharing a node that moving food pushed wake (their activity
// field says so, and the next substep stores them with the moving ones).
template <typename Real>
void Solver<Real>::WakePushedFrozenParticles() {
  FrozenLoad& frozen = *frozen_;
  if (!frozen.any_pushed) return;
  Particles<Real>& p = particles_;
  const Real inv_dx = Real(1.0 / config().dx_m);
  auto pushed = [&](std::size_t q) {
    int base[3];
    for (int axis = 0; axis < 3; ++axis) base[axis] = CellOf(p.position[axis][q], inv_dx) - frozen.origin[axis];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < 3; ++k) {
          // A frozen particle's stencil lies in the load's box, which was fitted to them.
          if (frozen.pushed[BoxIndex(frozen.dims, base[0] + i, base[1] + j, base[2] + k)]) return true;
        }
      }
    }
    return false;
  };
  for (std::size_t q = active_count_; q < p.size(); ++q) {
    if (pushed(q)) p.activity[q] = 0;
  }
  frozen.any_pushed = false;
  std::fill(frozen.pushed.begin(), frozen.pushed.end(), std::uint8_t(0));
}

template void Solver<float>::SetObjectAsleep(std::uint16_t, bool);
template void Solver<double>::SetObjectAsleep(std::uint16_t, bool);
template void Solver<float>::WakePushedFrozenParticles();
template void Solver<double>::WakePushedFrozenParticles();
template void Solver<float>::UpdateActivity(const SubstepContext&);
template void Solver<double>::UpdateActivity(const SubstepContext&);
template void Solver<float>::BuildFrozenLoad(const SubstepContext&);
template void Solver<double>::BuildFrozenLoad(const SubstepContext&);
template void Solver<float>::AddFrozenLoad(const SubstepContext&);
template void Solver<double>::AddFrozenLoad(const SubstepContext&);
template void Solver<float>::MarkPushedFrozenNodes();
template void Solver<double>::MarkPushedFrozenNodes();

}  // namespace culinarycut::mpm
