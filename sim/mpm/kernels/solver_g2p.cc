// G2P: each particle gathers velocity and the affine field from its 27 nodes, then moves, updates F
// (J clamped), grows damage near the edge and feels the tip force. Particles are independent here,
// so they go in storage order; the totals are summed per fixed chunk.
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "sim/mpm/kernels/solver_internals.h"
#include "sim/mpm/kernels/transfer_stencil.h"
#include "sim/mpm/physics/viscoelasticity.h"

namespace culinarycut::mpm {
namespace {

// v = sum w v_i, and per axis a the moment sum w v_i n_a with n_a in {0, 1, 2} the node's offset
// from the stencil's first node along a (cells): B = sum w v_i (x_i - x_p)^T follows from them.
// 4-vectors, lane 3 unused.
template <typename Real>
struct GatheredVelocity {
  Vector4<Real> v;
  Vector4<Real> moment[3];
};

// Sums along k within each row, then along j, then i (separable weights): short dependency
// chains and four accumulators instead of one chain of 27 adds. `node_at(row, k)` is the node at
// (i, j, k) given the row offset i stride_i + j stride_j.
template <typename Real, int W, typename NodeAt>
inline GatheredVelocity<Real> GatherStencil(const StencilLanes<Real, W>& stencil, int l,
                                            std::size_t stride_i, std::size_t stride_j,
                                            NodeAt&& node_at) {
  const auto& w = stencil.w;
  const Vector4<Real> w_k[3] = {Vector4<Real>::Constant(w[2][0][l]),
                                Vector4<Real>::Constant(w[2][1][l]),
                                Vector4<Real>::Constant(w[2][2][l])};
  Vector4<Real> plane[3];  // sum over j, k of w v_i, per i
  Vector4<Real> moment_j = Vector4<Real>::Zero();
  Vector4<Real> moment_k = Vector4<Real>::Zero();
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) {
    Vector4<Real> row[3];  // sum over k of w v_i, per j
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const Real weight_ij = w[0][i][l] * w[1][j][l];
      const std::size_t offset = i * stride_i + j * stride_j;
      const Vector4<Real> t0 = w_k[0].cwiseProduct(node_at(offset, 0));
      const Vector4<Real> t1 = w_k[1].cwiseProduct(node_at(offset, 1));
      const Vector4<Real> t2 = w_k[2].cwiseProduct(node_at(offset, 2));
      row[j] = weight_ij * ((t0 + t1) + t2);
      moment_k += weight_ij * (t1 + (t2 + t2));
    }
    plane[i] = (row[0] + row[1]) + row[2];
    moment_j += row[1] + (row[2] + row[2]);
  }
  GatheredVelocity<Real> sums;
  sums.v = (plane[0] + plane[1]) + plane[2];
  sums.moment[0] = plane[1] + (plane[2] + plane[2]);
  sums.moment[1] = moment_j;
  sums.moment[2] = moment_k;
  return sums;
}

// det of the row-major 3x3 matrix in lane l (Eigen's cofactor expansion, same rounding).
template <typename Real, int W>
inline Real Determinant3(const Real (&F)[9][W], int l) {
  return F[0][l] * (F[4][l] * F[8][l] - F[5][l] * F[7][l]) -
         F[1][l] * (F[3][l] * F[8][l] - F[5][l] * F[6][l]) +
         F[2][l] * (F[3][l] * F[7][l] - F[4][l] * F[6][l]);
}

constexpr int kLanes = 8;  // particles updated together (SIMD lanes)

}  // namespace

// Team, the last stage: every thread calls it; each chunk's totals go to work.particle_chunks (Substep sums them).
template <typename Real>
void Solver<Real>::GridToParticles(const SubstepContext& context, const ContactState& contact) {
  Particles<Real>& p = particles_;
  const Grid& grid = *grid_;
  Workspace& work = *workspace_;
  const CuttingParameters& cutting = config().cutting;
  const ParticleBlocks& blocks = work.blocks;
  const std::size_t n = active_count_;  // the frozen particles (stored last) stay as they are
  const double dt_s = context.dt_s;
  const double dx = context.dx_m;
  const double band_m = context.band_m;
  const Real dt = Real(dt_s);
  const Real dx_r = Real(dx);
  const Real inv_dx = Real(1.0 / dx);
  const Real c_scale = Real(4) * inv_dx * inv_dx;
  const Real j_min = Real(config().j_min);
  const Real j_max = Real(config().j_max);
  const Real max_speed = Real(config().max_particle_speed_m_s);
  const bool split_on = context.split_on;
  const bool damage_gate = contact.damage_gate;
  const bool tip_on = contact.tip_on;
  const Eigen::AlignedBox3d damage_box =
      context.knife_on ? knife_->BladeBounds(band_m) : Eigen::AlignedBox3d();
  // The damage box in Real, rounded outwards: a cheap test in lanes before the exact one.
  Real edge_box_low[3], edge_box_high[3];
  constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    edge_box_low[axis] = std::nextafter(Real(damage_box.min()[axis]), -kInfinity);
    edge_box_high[axis] = std::nextafter(Real(damage_box.max()[axis]), kInfinity);
  }
  const Eigen::Vector3d blade_normal = context.knife_on
                                           ? Eigen::Vector3d(knife_->motion().pose.linear().col(1))
                                           : Eigen::Vector3d::UnitY();
  // Raw pointers: the hot loop reads no vector headers.
  Real* const position[3] = {p.position[0].data(), p.position[1].data(), p.position[2].data()};
  Real* const velocity[3] = {p.velocity[0].data(), p.velocity[1].data(), p.velocity[2].data()};
  Real* F_of[9];
  Real* C_of[9];
  for (int k = 0; k < 9; ++k) {
    F_of[k] = p.F[k].data();
    C_of[k] = p.C[k].data();
  }
  const Real* const mass = p.mass.data();
  Real* const damage = p.damage.data();
  const std::int8_t* const blade_side = p.blade_side.data();
  const std::uint32_t* const block_of = blocks.block_of.data();
  const std::uint8_t* const block_near_split = blocks.near_split.data();
  const GridNode<Real>* const nodes = grid.node.data();
  const std::int32_t* const split_slot = grid.split_slot.data();
  const GridNode<Real>* const layer[2] = {grid.layer[0].data(), grid.layer[1].data()};
  const std::size_t stride_i = grid.stride_i();
  const std::size_t stride_j = grid.stride_j();
  // Each material's Maxwell branch over this substep (physics/viscoelasticity.h); a few materials at
  // most, so a small table on the stack.
  constexpr std::size_t kMaxwellTable = kMaxMaxwellMaterials;
  struct MaxwellBranch {
    Real shear_modulus_pa = 0;
    MaxwellStep step;
  };
  MaxwellBranch maxwell_of[kMaxwellTable];
  bool any_maxwell = false;
  for (std::size_t m = 0; m < materials().size() && m < kMaxwellTable; ++m) {
    const Material& material = materials()[m];
    maxwell_of[m] = {Real(material.maxwell_shear_modulus_pa()),
                     MaxwellStepFor(dt_s, material.maxwell_relaxation_time_s)};
    any_maxwell = any_maxwell || maxwell_of[m].shear_modulus_pa > Real(0);
  }
  const std::uint16_t* const material_of = p.material.data();

  // One particle's gather from its 27 nodes into lane l of (v, C).
  auto gather = [&](std::size_t q, int l, const auto& stencil, auto& v, auto& C) {
    const std::size_t first = stencil.first_node[l];
    GatheredVelocity<Real> sums;
    if (!(split_on && block_near_split[block_of[q]])) {
      const GridNode<Real>* const corner = nodes + first;
      sums = GatherStencil(stencil, l, stride_i, stride_j,
                           [corner](std::size_t row, int k) -> const GridNode<Real>& {
                             return corner[row + k];
                           });
    } else {
      // Near the blade: a split node gives this particle its own side's layer.
      const GridNode<Real>* const own_layer = layer[blade_side[q] > 0 ? 1 : 0];
      sums = GatherStencil(stencil, l, stride_i, stride_j,
                           [&](std::size_t row, int k) -> const GridNode<Real>& {
                             const std::size_t node = first + row + k;
                             const std::int32_t slot = split_slot[node];
                             return slot >= 0 ? own_layer[slot] : nodes[node];
                           });
    }
    // C = 4 / dx^2 B, B = sum w v_i (n dx)^T - v (fx dx)^T.
    for (int a = 0; a < 3; ++a) {
      const Vector4<Real> column = (sums.moment[a] - stencil.fx[a][l] * sums.v) * dx_r;
      for (int r = 0; r < 3; ++r) C[3 * r + a][l] = c_scale * column[r];
    }
    for (int axis = 0; axis < 3; ++axis) v[axis][l] = sums.v[axis];
  };

  const bool prefetch = n >= kPrefetchFromParticles;
  // Particles q0 .. q0 + W - 1 (W a compile-time constant, so the lane loops vectorise).
  auto update_batch = [&](std::size_t q0, auto width, ParticleTotals& totals) {
    constexpr int W = decltype(width)::value;
    // F is read and written, C written: past the caches the loop waits on F's loads unless it asks
    // ahead (0.92x the time at 100k particles); within them asking costs 2 % (10k).
    for (int k = 0; k < 9 && W > 1 && prefetch; ++k) {
      __builtin_prefetch(F_of[k] + q0 + kPrefetchAhead, 1);
      __builtin_prefetch(C_of[k] + q0 + kPrefetchAhead, 1);
    }
    Real lane_position[3][W];
    for (int axis = 0; axis < 3; ++axis) {
      for (int l = 0; l < W; ++l) lane_position[axis][l] = position[axis][q0 + l];
    }
    StencilLanes<Real, W> stencil;
    StencilBatch<Real, W>(lane_position, inv_dx, grid.origin, grid.dims, &stencil);
    Real v[3][W], C[9][W];
    for (int l = 0; l < W; ++l) gather(q0 + l, l, stencil, v, C);

    // Rare, one particle at a time: damage and the tip force near the edge (a float box test
    // in lanes first, the exact one after).
    bool near_edge[W];
    for (int l = 0; l < W; ++l) {
      near_edge[l] = damage_gate || tip_on;
      for (int axis = 0; axis < 3; ++axis) {
        const Real x = position[axis][q0 + l];
        near_edge[l] = near_edge[l] && x >= edge_box_low[axis] && x <= edge_box_high[axis];
      }
    }
    for (int l = 0; l < W; ++l) {
      if (!near_edge[l]) continue;
      const std::size_t q = q0 + l;
      const Eigen::Vector3d x(position[0][q], position[1][q], position[2][q]);
      if (!damage_box.contains(x)) continue;
      // Damage where the edge presses into the food fast enough (paper: gated by c-hat, the
      // approach speed and the stroke direction, inside the blade band).
      if (damage_gate && damage[q] < Real(1) && knife_->HeightAboveEdge(x) < band_m) {
        // Only at the edge: the flat faces push the cut sides apart but do not cut them.
        const SdfSample sample = knife_->Blade(x);
        if (std::abs(sample.distance_m) < band_m) {
          // The velocity it came in with: contact has already removed the approach from v.
          const Eigen::Vector3d v_start(velocity[0][q], velocity[1][q], velocity[2][q]);
          const Eigen::Vector3d relative = v_start - knife_->motion().VelocityAt(x);
          const double normal_speed = relative.dot(sample.normal);
          if (normal_speed <= -context.v_threshold_m_s) {
            const double increment = cutting.damage_per_band * (-normal_speed * dt_s) / band_m;
            damage[q] = std::min(Real(1), damage[q] + Real(increment));
            ++totals.damaged;
          }
        }
      }
      // Tip force: push labelled particles near the edge away from the blade plane.
      if (tip_on && blade_side[q] != 0 &&
          std::abs(knife_->HeightAboveEdge(x)) < cutting.tip_band_cells * dx &&
          knife_->WithinBladeLength(x)) {
        // A force on the real mass: on scaled mass (solver_config.h) the acceleration is 1 / s of it.
        const Eigen::Vector3d push = (blade_side[q] > 0 ? 1.0 : -1.0) *
                                     (cutting.tip_acceleration_m_s2 / config().mass_scaling) * dt_s * blade_normal;
        for (int axis = 0; axis < 3; ++axis) v[axis][l] += Real(push[axis]);
        totals.particle_impulse += double(mass[q]) * push;
      }
    }

    // Speed cap (rare), then move.
    Real speed[W];
    for (int l = 0; l < W; ++l) {
      speed[l] = std::sqrt(v[0][l] * v[0][l] + (v[1][l] * v[1][l] + v[2][l] * v[2][l]));
    }
    for (int l = 0; l < W; ++l) {
      if (!(speed[l] > max_speed)) continue;
      const Real scale = max_speed / speed[l];
      Eigen::Vector3d change;
      for (int axis = 0; axis < 3; ++axis) {
        const Real uncapped = v[axis][l];
        v[axis][l] *= scale;
        change[axis] = double(v[axis][l] - uncapped);
      }
      ++totals.speed_caps;
      totals.particle_impulse += double(mass[q0 + l]) * change;
    }
    for (int axis = 0; axis < 3; ++axis) {
      for (int l = 0; l < W; ++l) {
        velocity[axis][q0 + l] = v[axis][l];
        position[axis][q0 + l] += dt * v[axis][l];
      }
    }
    for (int k = 0; k < 9; ++k) {
      for (int l = 0; l < W; ++l) C_of[k][q0 + l] = C[k][l];
    }

    // F <- (I + dt C) F (paper eq. Fupdate), then J clamped isotropically to [j_min, j_max].
    Real F[9][W], J[W], M[9][W], F_old[9][W];
    for (int k = 0; k < 9; ++k) {
      for (int l = 0; l < W; ++l) {
        M[k][l] = Real(k % 4 == 0 ? 1 : 0) + dt * C[k][l];
        F_old[k][l] = F_of[k][q0 + l];
      }
    }
    for (int r = 0; r < 3; ++r) {
      for (int col = 0; col < 3; ++col) {
        for (int l = 0; l < W; ++l) {
          F[3 * r + col][l] = M[3 * r][l] * F_old[col][l] + (M[3 * r + 1][l] * F_old[3 + col][l] +
                                                             M[3 * r + 2][l] * F_old[6 + col][l]);
        }
      }
    }
    for (int l = 0; l < W; ++l) J[l] = Determinant3(F, l);
    for (int l = 0; l < W; ++l) {
      if (J[l] >= j_min && J[l] <= j_max) continue;
      // Rare: scale F isotropically to the nearest bound, or reset it when J is no number.
      const bool usable = std::isfinite(J[l]) && J[l] > Real(0);
      const Real scale = usable ? std::cbrt(std::clamp(J[l], j_min, j_max) / J[l]) : Real(0);
      for (int k = 0; k < 9; ++k) F[k][l] = usable ? F[k][l] * scale : Real(k % 4 == 0 ? 1 : 0);
      J[l] = Determinant3(F, l);  // what the clamp achieved, not what it aimed at
      ++totals.j_clamps;
    }
    // A fully broken particle has no shear stiffness (mu (1 - D) = 0), so its stress depends on J alone
    // (constitutive.h): it keeps J^(1/3) I. Else shear flow past it stretches F without bound while
    // J stays clamped, until the polar decomposition's float cofactors cancel to nothing (a random
    // policy's sweep through a cucumber: |F| 3,000, then NaN). Its stress and J are unchanged by this.
    for (int l = 0; l < W; ++l) {
      if (!(damage[q0 + l] >= Real(1))) continue;
      const Real stretch = std::cbrt(J[l]);
      for (int k = 0; k < 9; ++k) F[k][l] = k % 4 == 0 ? stretch : Real(0);
    }
    for (int k = 0; k < 9; ++k) {
      for (int l = 0; l < W; ++l) F_of[k][q0 + l] = F[k][l];
    }
    // The Maxwell branch relaxes and takes up the substep's strain rate (C is the velocity gradient).
    for (int l = 0; l < W && any_maxwell; ++l) {
      const std::size_t q = q0 + l;
      const MaxwellBranch& branch = maxwell_of[material_of[q]];
      if (!(branch.shear_modulus_pa > Real(0))) continue;
      Real velocity_gradient[9], stress[6];
      for (int k = 0; k < 9; ++k) velocity_gradient[k] = C[k][l];
      for (int k = 0; k < 6; ++k) stress[k] = p.maxwell_stress[k][q];
      UpdateMaxwellStress(velocity_gradient, dt, branch.shear_modulus_pa, branch.step, stress);
      for (int k = 0; k < 6; ++k) p.maxwell_stress[k][q] = stress[k];
    }
    // Totals in particle order: the same sums whatever the thread count.
    for (int l = 0; l < W; ++l) {
      totals.j_min = std::min(totals.j_min, double(J[l]));
      totals.j_max = std::max(totals.j_max, double(J[l]));
      const double m = mass[q0 + l];
      for (int axis = 0; axis < 3; ++axis) totals.momentum[axis] += m * v[axis][l];
      const Real speed_sq = v[0][l] * v[0][l] + (v[1][l] * v[1][l] + v[2][l] * v[2][l]);
      totals.kinetic_energy += 0.5 * m * double(speed_sq);
      // The fastest particle bounds the next substep's dt (StableTimestep with a particle speed).
      totals.max_speed_sq = std::max(totals.max_speed_sq, SquaredSpeed(v[0][l], v[1][l], v[2][l]));
    }
  };

  const std::size_t particle_chunks = ChunkCount(n);  // work.particle_chunks: zeroed beforehand
  // No barrier after it: the parallel region's end is one.
#pragma omp for schedule(dynamic, 1) nowait
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(particle_chunks); ++c) {
    ParticleTotals& totals = work.particle_chunks[c];
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    std::size_t q0 = c * kChunk;
    for (; q0 + kLanes <= end; q0 += kLanes) {
      update_batch(q0, std::integral_constant<int, kLanes>{}, totals);
    }
    for (; q0 < end; ++q0) update_batch(q0, std::integral_constant<int, 1>{}, totals);
  }
}

template void Solver<float>::GridToParticles(const SubstepContext&, const ContactState&);
template void Solver<double>::GridToParticles(const SubstepContext&, const ContactState&);

}  // namespace culinarycut::mpm
