#include "sim/mpm/solver.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/mpm/constitutive.h"
#include "sim/mpm/grid_contact.h"
#include "sim/mpm/polar_batch.h"
#include "sim/mpm/stress_batch.h"
#include "sim/mpm/substep_totals.h"
#include "sim/mpm/transfer_stencil.h"

namespace culinarycut::mpm {
namespace {

constexpr int kBlockCells = 4;        // P2G block edge; same-colour blocks never share a node
constexpr double kContactStrengthScale = 0.35;  // c_norm = 0.35 dx / dt (paper)
// Grid nodes feel the blade within half a cell of its surface: a thin, sharp edge between two
// node layers would otherwise never touch them, and the edge could not press on the food.
constexpr double kBladeContactOffsetCells = 0.5;
// Nodes split by side only once the edge is this far below them; the edge itself presses on
// unsplit nodes, which is where cutting resistance and damage come from.
constexpr double kSplitAboveEdgeCells = 0.5;

template <typename Real>
using Vector3 = Eigen::Matrix<Real, 3, 1>;

constexpr std::uint64_t kReorderEverySubsteps = 16;
constexpr double kMaxCellIndex = 1 << 29;  // |x| / dx beyond this would overflow the cell ints
constexpr double kMaxGridNodes = 4e8;      // 6.4 GB of float nodes: a blow-up, not a scene

}  // namespace

// The bounded grid box: nodes (origin + (i, j, k)) * dx for i < dims.x() etc. Near the blade,
// "split" nodes keep one layer per blade side (CPIC-style) so the sides never share momentum.
// One grid node: (momentum x, y, z, mass) after P2G, (velocity, mass) after the grid update. One
// 4-vector: a transfer adds to it with one SIMD operation and touches one cache line.
template <typename Real>
using Vector4 = Eigen::Matrix<Real, 4, 1>;
template <typename Real>
using GridNode = Vector4<Real>;

template <typename Real>
struct Solver<Real>::Grid {
  Eigen::Vector3i origin = Eigen::Vector3i::Zero();  // global index of node (0, 0, 0)
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<GridNode<Real>> node;
  std::vector<std::int32_t> split_slot;              // -1, or this node's slot in the layers
  std::vector<std::size_t> split_nodes;              // node index of each slot
  std::array<std::vector<GridNode<Real>>, 2> layer;  // [side: 0 negative, 1 positive][slot]

  std::size_t size() const {
    return static_cast<std::size_t>(dims.x()) * dims.y() * dims.z();
  }
  std::size_t Index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * dims.y() + j) * dims.z() + k;
  }
};

template <typename Real>
struct Solver<Real>::Workspace {
  std::vector<std::uint32_t> order;          // particles sorted by P2G block
  std::vector<std::uint32_t> block_start;    // offsets into `order`, one past the last block
  std::array<std::vector<std::uint32_t>, 8> blocks_of_colour;
  std::vector<GridTotals> grid_chunks;
  std::vector<ParticleTotals> particle_chunks;
  std::array<std::vector<Real>, 9> affine;   // P2G: -dt vol 4/dx^2 tau + m C per particle
  std::uint64_t substeps_since_reorder = 0;
};

void ValidateSolverConfig(const SolverConfig& config) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument("solver config: " + message);
  };
  require(config.dx_m > 0.0 && std::isfinite(config.dx_m), "dx_m must be > 0");
  require(config.cfl > 0.0 && config.cfl <= 1.0, "cfl must lie in (0, 1]");
  require(config.max_dt_s > 0.0, "max_dt_s must be > 0");
  require(config.j_min > 0.0 && config.j_min < 1.0 && config.j_max > 1.0,
          "need 0 < j_min < 1 < j_max");
  require(config.max_particle_speed_m_s > 0.0 && config.max_grid_speed_m_s > 0.0,
          "speed caps must be > 0");
  require(config.grid_damping_per_s >= 0.0, "grid_damping_per_s must be >= 0");
  require(config.gravity_m_s2.allFinite(), "gravity must be finite");
  require(config.grid_margin_cells >= 1, "grid_margin_cells must be >= 1");
  require(config.threads >= 1, "threads must be >= 1");
  const CuttingParameters& cutting = config.cutting;
  require(cutting.band0_m > 0.0 && cutting.band_reference_dx_m > 0.0, "band0_m and "
          "band_reference_dx_m must be > 0");
  require(cutting.v_hat >= 0.0 && cutting.c_hat_min >= 0.0 && cutting.damage_per_band >= 0.0,
          "v_hat, c_hat_min and damage_per_band must be >= 0");
  require(cutting.k2_reference_per_s >= 0.0 && cutting.k2_reference_youngs_pa > 0.0 &&
              cutting.k2_reference_yield_pa > 0.0,
          "k2 parameters must be positive");
  require(cutting.tip_acceleration_m_s2 >= 0.0 && cutting.tip_band_cells >= 0.0,
          "tip force parameters must be >= 0");
}

template <typename Real>
Solver<Real>::Solver(const SolverConfig& config, std::vector<Material> materials)
    : config_(config),
      materials_(std::move(materials)),
      grid_(std::make_unique<Grid>()),
      workspace_(std::make_unique<Workspace>()) {
  ValidateSolverConfig(config_);
  if (materials_.empty()) throw std::invalid_argument("solver: give at least one material");
  for (const Material& material : materials_) ValidateMaterial(material);
}

template <typename Real>
Solver<Real>::~Solver() = default;
template <typename Real>
Solver<Real>::Solver(Solver&&) noexcept = default;
template <typename Real>
Solver<Real>& Solver<Real>::operator=(Solver&&) noexcept = default;

template <typename Real>
void Solver<Real>::SetKnife(const KnifeGeometry& geometry) {
  knife_ = std::make_unique<KnifeSdf>(geometry, config_.dx_m);
}

template <typename Real>
void Solver<Real>::SetKnifeMotion(const RigidMotion& tcp_motion) {
  if (!knife_) throw std::logic_error("SetKnifeMotion before SetKnife");
  knife_->SetMotion(tcp_motion);
}

template <typename Real>
void Solver<Real>::SetBoard(const Eigen::Vector3d& size_m, const RigidMotion& motion) {
  board_.emplace(size_m, motion);
}

template <typename Real>
void Solver<Real>::SetTable(double height_m) {
  table_.emplace(height_m);
}

template <typename Real>
std::uint64_t Solver<Real>::substeps_taken() const {
  return workspace_->substeps_since_reorder;
}

template <typename Real>
void Solver<Real>::RestoreSubstepsTaken(std::uint64_t count) {
  workspace_->substeps_since_reorder = count;
}

template <typename Real>
double Solver<Real>::StableTimestep() const {
  double fastest_m_s = 0.0;
  for (const Material& material : materials_) {
    fastest_m_s = std::max(fastest_m_s, material.dilatational_wave_speed_m_s());
  }
  return std::min(config_.max_dt_s, config_.cfl * config_.dx_m / fastest_m_s);
}


template <typename Real>
SubstepDiagnostics Solver<Real>::Substep(double dt_s) {
  if (!(dt_s > 0.0 && std::isfinite(dt_s))) {
    throw std::invalid_argument("Substep: dt_s must be a finite time > 0 s");
  }
  SubstepDiagnostics diagnostics;
  diagnostics.dt_s = dt_s;
  Particles<Real>& p = particles_;
  const std::size_t n = p.size();
  if (n == 0) return diagnostics;
  Grid& grid = *grid_;
  Workspace& work = *workspace_;
  const Effects& effects = config_.effects;
  const CuttingParameters& cutting = config_.cutting;
  const int threads = config_.threads;
  const double dx = config_.dx_m;
  const Real dx_r = Real(dx);
  const Real inv_dx = Real(1.0 / dx);
  const Real dt = Real(dt_s);
  const bool knife_on = knife_ != nullptr;
  const bool split_on = knife_on && effects.two_sided_blade;
  // Resolution-invariant cutting thresholds (paper): band and v_th rescale with dx and dt.
  const double band_m =
      cutting.band0_m * std::pow(cutting.band_reference_dx_m / dx, cutting.band_gamma);
  const double v_threshold_m_s = (dx / dt_s) * cutting.v_hat;
  const double blade_half_m = knife_on ? 0.5 * knife_->effective_thickness_m() : 0.0;
  // Nodes this close to the blade's mid-plane, at or above the edge, are split by side; particles
  // get a side label a little further out, so every particle touching a split node has one.
  const double split_half_width_m = blade_half_m + 2.0 * dx;
  const double half_length_m = knife_on ? 0.5 * knife_->geometry().blade_length_m : 0.0;
  const double blade_height_m = knife_on ? knife_->geometry().blade_height_m : 0.0;
  // A particle's stencil reaches 1.5 cells along each grid axis, so up to 1.5 sqrt(3) cells in
  // the blade's own frame whatever the knife's pose: particles within that reach of a split node
  // carry a label.
  const double stencil_reach_m = 1.5 * std::sqrt(3.0) * dx + 1e-9;

  using Clock = std::chrono::steady_clock;
  auto elapsed_ms = [](Clock::time_point since) {
    return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
  };
  Clock::time_point stage_start = Clock::now();

  // --- Grid box around the particles (only the object's neighbourhood) ---------------------
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
  diagnostics.grid_cells = grid.dims;
  const std::size_t nodes = grid.size();
  grid.node.assign(nodes, GridNode<Real>::Zero());
  auto node_position = [&](int i, int j, int k) {
    return Eigen::Vector3d((grid.origin.x() + i) * dx, (grid.origin.y() + j) * dx,
                           (grid.origin.z() + k) * dx);
  };

  // --- Split nodes and side labels near the blade (CPIC) -----------------------------------
  grid.split_slot.assign(split_on ? nodes : 0, -1);
  grid.split_nodes.clear();
  if (split_on) {
    const Eigen::AlignedBox3d region = knife_->BladeBounds(split_half_width_m + dx);
    Eigen::Vector3i lo, hi;
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = std::max(0, static_cast<int>(std::floor(region.min()[axis] / dx)) - grid.origin[axis]);
      hi[axis] = std::min(grid.dims[axis] - 1,
                          static_cast<int>(std::ceil(region.max()[axis] / dx)) - grid.origin[axis]);
    }
    for (int i = lo.x(); i <= hi.x(); ++i) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int k = lo.z(); k <= hi.z(); ++k) {
          const Eigen::Vector3d local = knife_->ToTcpFrame(node_position(i, j, k));
          const double height_m = -local.z();
          if (std::abs(local.y()) < split_half_width_m && std::abs(local.x()) <= half_length_m &&
              height_m >= kSplitAboveEdgeCells * dx && height_m <= blade_height_m + 0.5 * dx) {
            const std::size_t index = grid.Index(i, j, k);
            grid.split_slot[index] = static_cast<std::int32_t>(grid.split_nodes.size());
            grid.split_nodes.push_back(index);
          }
        }
      }
    }
    const std::size_t slots = grid.split_nodes.size();
    for (int side = 0; side < 2; ++side) {
      grid.layer[side].assign(slots, GridNode<Real>::Zero());
    }
    // A particle near the blade takes the side it is on, and keeps it once the edge has passed it
    // (from then on the blade stands between the sides); labels are dropped once it is clear of
    // the blade, so the next cut labels afresh.
    const Eigen::AlignedBox3d label_region =
        knife_->BladeBounds(split_half_width_m + stencil_reach_m + dx);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t q = 0; q < static_cast<std::int64_t>(n); ++q) {
      const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);
      if (!label_region.contains(x)) {
        p.blade_side[q] = static_cast<std::int8_t>(BladeSide::kUnassigned);
        continue;
      }
      const Eigen::Vector3d local = knife_->ToTcpFrame(x);
      const double side_m = local.y();
      const double height_m = -local.z();
      const bool near = std::abs(local.x()) <= half_length_m + stencil_reach_m &&
                        height_m >= kSplitAboveEdgeCells * dx - stencil_reach_m &&
                        height_m <= blade_height_m + 0.5 * dx + stencil_reach_m &&
                        std::abs(side_m) < split_half_width_m + stencil_reach_m;
      if (!near) {
        p.blade_side[q] = static_cast<std::int8_t>(BladeSide::kUnassigned);
      } else if (p.blade_side[q] == static_cast<std::int8_t>(BladeSide::kUnassigned) ||
                 height_m < 0.0) {
        p.blade_side[q] = static_cast<std::int8_t>(side_m >= 0.0 ? BladeSide::kPositive
                                                                 : BladeSide::kNegative);
      }
    }
  } else {
    std::fill(p.blade_side.begin(), p.blade_side.end(), std::int8_t(0));
  }

  // --- Sort particles by P2G block (stable counting sort: deterministic order) -------------
  const Eigen::Vector3i blocks = (grid.dims.array() + kBlockCells - 1) / kBlockCells;
  const std::size_t block_count = static_cast<std::size_t>(blocks.x()) * blocks.y() * blocks.z();
  std::vector<std::uint32_t> block_of(n);
  auto base_cell = [&](std::size_t q, int axis) {
    return CellOf(p.position[axis][q], inv_dx) - grid.origin[axis];
  };
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t q = 0; q < static_cast<std::int64_t>(n); ++q) {
    const int bx = base_cell(q, 0) / kBlockCells;
    const int by = base_cell(q, 1) / kBlockCells;
    const int bz = base_cell(q, 2) / kBlockCells;
    block_of[q] = static_cast<std::uint32_t>((static_cast<std::size_t>(bx) * blocks.y() + by) *
                                                 blocks.z() + bz);
  }
  work.block_start.assign(block_count + 1, 0);
  for (std::size_t q = 0; q < n; ++q) ++work.block_start[block_of[q] + 1];
  for (std::size_t b = 0; b < block_count; ++b) work.block_start[b + 1] += work.block_start[b];
  work.order.resize(n);
  {
    std::vector<std::uint32_t> fill(work.block_start.begin(), work.block_start.end() - 1);
    for (std::size_t q = 0; q < n; ++q) work.order[fill[block_of[q]]++] = static_cast<std::uint32_t>(q);
  }
  // Every few substeps, store the particles in block order, so the transfers stream through
  // memory instead of jumping (deterministic: the order depends only on the positions).
  if (work.substeps_since_reorder++ % kReorderEverySubsteps == 0) {
    ReorderParticles(work.order, &p);
    std::vector<std::uint32_t> reordered_block(n);
    for (std::size_t s = 0; s < n; ++s) reordered_block[s] = block_of[work.order[s]];
    block_of.swap(reordered_block);
    for (std::size_t s = 0; s < n; ++s) work.order[s] = static_cast<std::uint32_t>(s);
  }
  for (auto& list : work.blocks_of_colour) list.clear();
  for (std::size_t b = 0; b < block_count; ++b) {
    if (work.block_start[b] == work.block_start[b + 1]) continue;
    const int bz = static_cast<int>(b % blocks.z());
    const int by = static_cast<int>((b / blocks.z()) % blocks.y());
    const int bx = static_cast<int>(b / (static_cast<std::size_t>(blocks.y()) * blocks.z()));
    work.blocks_of_colour[(bx & 1) | ((by & 1) << 1) | ((bz & 1) << 2)].push_back(
        static_cast<std::uint32_t>(b));
  }

  // Blocks whose particles can reach a split node: only their particles look up the layers.
  std::vector<std::uint8_t> block_near_split(block_count, 0);
  for (const std::size_t node : grid.split_nodes) {
    const int k = static_cast<int>(node % grid.dims.z());
    const int j = static_cast<int>((node / grid.dims.z()) % grid.dims.y());
    const int i = static_cast<int>(node / (static_cast<std::size_t>(grid.dims.y()) * grid.dims.z()));
    // A particle with base cell b touches nodes b .. b + 2.
    for (int bx = std::max(0, i - 2) / kBlockCells; bx <= std::min(blocks.x() - 1, i / kBlockCells); ++bx) {
      for (int by = std::max(0, j - 2) / kBlockCells; by <= std::min(blocks.y() - 1, j / kBlockCells); ++by) {
        for (int bz = std::max(0, k - 2) / kBlockCells; bz <= std::min(blocks.z() - 1, k / kBlockCells); ++bz) {
          block_near_split[(static_cast<std::size_t>(bx) * blocks.y() + by) * blocks.z() + bz] = 1;
        }
      }
    }
  }

  // Momentum before the step, for the momentum check (summed in fixed chunks: thread-independent).
  std::vector<Eigen::Vector3d> momentum_of_chunk(
      effects.force_sensing ? ChunkCount(n) : 0, Eigen::Vector3d::Zero());
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(momentum_of_chunk.size()); ++c) {
    const std::size_t end_q = std::min(n, (c + 1) * kChunk);
    for (std::size_t q = c * kChunk; q < end_q; ++q) {
      for (int axis = 0; axis < 3; ++axis) {
        momentum_of_chunk[c][axis] += double(p.mass[q]) * p.velocity[axis][q];
      }
    }
  }
  Eigen::Vector3d momentum_before = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& chunk : momentum_of_chunk) momentum_before += chunk;

  diagnostics.setup_ms = elapsed_ms(stage_start);
  stage_start = Clock::now();

  // --- P2G, part 1: stress (plastic return, damaged corotated) -> each particle's affine
  // momentum matrix, in particle order (independent per particle, streams the arrays) ---------
  const Real stress_scale = -dt * Real(4) * inv_dx * inv_dx;
  for (auto& component : work.affine) component.resize(n);
  const std::size_t stress_chunks = ChunkCount(n);
  std::vector<double> elastic_energy_of_chunk(stress_chunks, 0.0);
  // Stress of one particle given its rotation R; returns its elastic energy (J).
  // J2 radial return of particle q (F updated in place and stored); false when it did not flow.
  auto plastic_return = [&](std::size_t q, const Matrix3<Real>& R, Matrix3<Real>* F) {
    const Material& material = materials_[p.material[q]];
    if (!effects.plasticity || material.yield_stress_pa <= 0.0) return false;
    const Real fraction = material.viscoplastic_relaxation_time_s > 0.0
                              ? Real(dt_s / (material.viscoplastic_relaxation_time_s + dt_s))
                              : Real(1);
    const Real plastic = ReturnToYieldSurface(F, R, Real(material.yield_stress_pa),
                                              Real(material.shear_modulus_pa()), fraction);
    if (plastic <= Real(0)) return false;
    p.plastic_strain[q] += plastic;
    for (int k = 0; k < 9; ++k) p.F[k][q] = (*F)(k / 3, k % 3);
    return true;
  };
  auto particle_stress = [&](std::size_t q, const Matrix3<Real>& R) {
    Matrix3<Real> F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
    const Material& material = materials_[p.material[q]];
    plastic_return(q, R, &F);
    const Real damage_scale = Real(1) - p.damage[q];
    const Lame<Real> lame{Real(material.shear_modulus_pa()) * damage_scale,
                          Real(material.lame_lambda_pa()) * damage_scale};
    const Real J = F.determinant();
    const Matrix3<Real> tau = CorotatedKirchhoffStress(F, R, J, lame);
    const Real volume_scale = stress_scale * p.volume[q];
    const Real m = p.mass[q];
    for (int k = 0; k < 9; ++k) work.affine[k][q] = volume_scale * tau(k / 3, k % 3) + m * p.C[k][q];
    return double(p.volume[q]) * CorotatedEnergyDensity(F, R, J, lame);
  };
  // Per-material constants, computed once per substep rather than per particle.
  struct MaterialConstants {
    Real mu;                    // Pa
    Real lambda;                // Pa
    Real yield_test_strain_sq;  // plastic flow is possible above ~0.7 of the yield strain
  };
  std::vector<MaterialConstants> material_constants;
  bool any_plastic = false;
  for (const Material& material : materials_) {
    // The same early-out as ReturnToYieldSurface (see YieldTestFraction).
    const double full_yield_strain =
        std::sqrt(2.0 / 3.0) * material.yield_stress_pa / (2.0 * material.shear_modulus_pa());
    const double yield_strain = effects.plasticity && material.yield_stress_pa > 0.0
                                    ? YieldTestFraction(full_yield_strain) * full_yield_strain
                                    : 1e15;
    any_plastic = any_plastic || yield_strain < 1e15;
    material_constants.push_back({Real(material.shear_modulus_pa()), Real(material.lame_lambda_pa()),
                                  Real(yield_strain * yield_strain)});
  }
  constexpr int kLanes = 8;  // particles whose polar rotations are computed together (SIMD)
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(stress_chunks); ++c) {
    double chunk_energy = 0.0;
    const std::size_t end_q = std::min(n, (c + 1) * kChunk);
    std::size_t q = c * kChunk;
    for (; q + kLanes <= end_q; q += kLanes) {
      Real F_lanes[9][kLanes], R_lanes[9][kLanes], C_lanes[9][kLanes], affine_lanes[9][kLanes];
      Real mu[kLanes], lambda[kLanes], volume_scale[kLanes], mass[kLanes], volume[kLanes];
      Real yield_strain_sq[kLanes], green_sq[kLanes], energy[kLanes];
      for (int k = 0; k < 9; ++k) {
        for (int l = 0; l < kLanes; ++l) {
          F_lanes[k][l] = p.F[k][q + l];
          C_lanes[k][l] = p.C[k][q + l];
        }
      }
      for (int l = 0; l < kLanes; ++l) {
        const MaterialConstants& material = material_constants[p.material[q + l]];
        const Real damage_scale = Real(1) - p.damage[q + l];
        mu[l] = material.mu * damage_scale;
        lambda[l] = material.lambda * damage_scale;
        volume[l] = p.volume[q + l];
        volume_scale[l] = stress_scale * volume[l];
        mass[l] = p.mass[q + l];
        yield_strain_sq[l] = material.yield_test_strain_sq;
      }
      PolarRotationBatch<Real, kLanes>(F_lanes, R_lanes);
      if (any_plastic) DeviatoricGreenStrainSquared<Real, kLanes>(F_lanes, green_sq);
      for (int l = 0; l < kLanes && any_plastic; ++l) {
        if (green_sq[l] < yield_strain_sq[l]) continue;
        // Rare: this particle may have yielded; return it to the yield surface one at a time.
        Matrix3<Real> F, R;
        for (int k = 0; k < 9; ++k) {
          F(k / 3, k % 3) = F_lanes[k][l];
          R(k / 3, k % 3) = R_lanes[k][l];
        }
        if (plastic_return(q + l, R, &F)) {
          for (int k = 0; k < 9; ++k) F_lanes[k][l] = F(k / 3, k % 3);
        }
      }
      CorotatedAffineBatch<Real, kLanes>(F_lanes, R_lanes, C_lanes, mu, lambda, volume_scale, mass,
                                         volume, affine_lanes, energy);
      for (int k = 0; k < 9; ++k) {
        for (int l = 0; l < kLanes; ++l) work.affine[k][q + l] = affine_lanes[k][l];
      }
      for (int l = 0; l < kLanes; ++l) chunk_energy += energy[l];
    }
    for (; q < end_q; ++q) {
      Matrix3<Real> F;
      for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
      chunk_energy += particle_stress(q, PolarRotation(F));
    }
    elastic_energy_of_chunk[c] = chunk_energy;
  }

  // --- P2G, part 2: mass and APIC momentum to the grid, block colour by block colour ---------
  for (int colour = 0; colour < 8; ++colour) {
    const auto& colour_blocks = work.blocks_of_colour[colour];
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::int64_t b = 0; b < static_cast<std::int64_t>(colour_blocks.size()); ++b) {
      const std::uint32_t block = colour_blocks[b];
      for (std::uint32_t s = work.block_start[block]; s < work.block_start[block + 1]; ++s) {
        const std::uint32_t q = work.order[s];
        Matrix3<Real> affine;
        for (int k = 0; k < 9; ++k) affine(k / 3, k % 3) = work.affine[k][q];
        const Real m = p.mass[q];
        const Stencil<Real> stencil = StencilOf(p, q, inv_dx, grid.origin);
        const int* base = stencil.base;
        const Real* fx = stencil.fx;
        const auto& w = stencil.w;
        // m v + A (x_node - x_p), built up axis by axis: A (x_node - x_p) = A (ijk dx - fx dx).
        const Vector3<Real> fx_m(fx[0] * dx_r, fx[1] * dx_r, fx[2] * dx_r);
        const Vector3<Real> at_particle =
            m * Vector3<Real>(p.velocity[0][q], p.velocity[1][q], p.velocity[2][q]) - affine * fx_m;
        // (momentum contribution, mass) as 4-vectors: one SIMD add per node.
        const Vector4<Real> at_particle4(at_particle.x(), at_particle.y(), at_particle.z(), m);
        Vector4<Real> step_i, step_j, step_k;
        step_i << affine.col(0) * dx_r, Real(0);
        step_j << affine.col(1) * dx_r, Real(0);
        step_k << affine.col(2) * dx_r, Real(0);
        const bool near_split = split_on && block_near_split[block];
        const int side = p.blade_side[q] > 0 ? 1 : 0;
        const std::size_t stride_i = static_cast<std::size_t>(grid.dims.y()) * grid.dims.z();
        const std::size_t stride_j = grid.dims.z();
        const std::size_t origin_node = grid.Index(base[0], base[1], base[2]);
        for (int i = 0; i < 3; ++i) {
          const Vector4<Real> value_i = at_particle4 + Real(i) * step_i;
          for (int j = 0; j < 3; ++j) {
            const Vector4<Real> value_ij = value_i + Real(j) * step_j;
            const Real weight_ij = w[0][i] * w[1][j];
            const std::size_t row = origin_node + i * stride_i + j * stride_j;
            for (int k = 0; k < 3; ++k) {
              const Real weight = weight_ij * w[2][k];
              const std::size_t node = row + k;
              const std::int32_t slot = near_split ? grid.split_slot[node] : -1;
              GridNode<Real>& target = slot >= 0 ? grid.layer[side][slot] : grid.node[node];
              target += weight * (value_ij + Real(k) * step_k);
            }
          }
        }
      }
    }
  }

  diagnostics.p2g_ms = elapsed_ms(stage_start);
  stage_start = Clock::now();

  // --- Grid update: velocity, gravity, damping, colliders; impulses for the force -----------
  const double friction = materials_.front().friction_coefficient;
  const bool use_friction = effects.friction;
  const Eigen::AlignedBox3d blade_box =
      knife_on ? knife_->BladeBounds(dx) : Eigen::AlignedBox3d();
  const Eigen::AlignedBox3d handle_box =
      knife_on ? knife_->HandleBounds(dx) : Eigen::AlignedBox3d();
  const Eigen::AlignedBox3d board_box = board_ ? board_->Bounds(dx) : Eigen::AlignedBox3d();
  const double damping = 1.0 / (1.0 + config_.grid_damping_per_s * dt_s);
  const Eigen::Vector3d blade_normal =
      knife_on ? Eigen::Vector3d(knife_->motion().pose.linear().col(1)) : Eigen::Vector3d::UnitY();

  const bool sense_force = effects.force_sensing;  // off: no impulse bookkeeping at all
  // Updates one node's velocity in place from its mass and momentum; `side` >= 0 for a layer of a
  // split node, whose blade is a wall at the blade face on that side.
  auto update_node = [&](const Eigen::Vector3d& x, GridNode<Real>* grid_node, int side,
                         GridTotals* totals) {
    const Real node_mass = (*grid_node)[3];
    if (node_mass <= Real(0)) return;
    const double m = node_mass;
    Eigen::Vector3d v = (grid_node->template head<3>() / node_mass).template cast<double>();
    // Gravity and damping; their impulses are counted for the momentum check.
    const Eigen::Vector3d v_undamped = v + dt_s * config_.gravity_m_s2;
    v = v_undamped * damping;
    if (sense_force) {
      totals->other_impulse += m * dt_s * config_.gravity_m_s2 + m * (v - v_undamped);
      totals->mass += m;
    }
    double approach = 0.0;
    if (board_ && board_box.contains(x)) {
      const SdfSample sample = board_->Sample(x);
      if (sample.distance_m < 0.0) {
        const Eigen::Vector3d before = v;
        if (ResolveContact(sample.normal, board_->motion().VelocityAt(x), friction, use_friction,
                           &v, &approach)) {
          if (sense_force) totals->board_impulse += m * (v - before);
        }
      }
    }
    if (table_ && x.z() <= table_->height_m()) {
      const Eigen::Vector3d before = v;
      if (ResolveContact(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), friction, use_friction,
                         &v, &approach)) {
        if (sense_force) totals->table_impulse += m * (v - before);
      }
    }
    if (knife_on) {
      if (side >= 0) {
        // The blade face on this side: material of this side may not move through it.
        const double sign = side == 1 ? 1.0 : -1.0;
        if (sign * knife_->SideOfBlade(x) < blade_half_m + kBladeContactOffsetCells * dx) {
          const Eigen::Vector3d before = v;
          if (ResolveContact(sign * blade_normal, knife_->motion().VelocityAt(x), friction,
                             use_friction, &v, &approach)) {
            if (sense_force) totals->blade_impulse += m * (v - before);
          }
        }
      } else if (blade_box.contains(x)) {
        const SdfSample sample = knife_->Blade(x);
        if (sample.distance_m < kBladeContactOffsetCells * dx) {
          const Eigen::Vector3d before = v;
          if (ResolveContact(sample.normal, knife_->motion().VelocityAt(x), friction, use_friction,
                             &v, &approach)) {
            if (sense_force) totals->blade_impulse += m * (v - before);
            totals->approach_speed_sum += approach;
          }
        }
      }
      if (handle_box.contains(x)) {
        const SdfSample sample = knife_->Handle(x);
        if (sample.distance_m < 0.0) {
          const Eigen::Vector3d before = v;
          if (ResolveContact(sample.normal, knife_->motion().VelocityAt(x), friction, use_friction,
                             &v, &approach)) {
            if (sense_force) totals->handle_impulse += m * (v - before);
          }
        }
      }
    }
    const double speed = v.norm();
    if (speed > config_.max_grid_speed_m_s) {
      const Eigen::Vector3d uncapped = v;
      v *= config_.max_grid_speed_m_s / speed;
      ++totals->speed_caps;
      if (sense_force) totals->other_impulse += m * (v - uncapped);
    }
    grid_node->template head<3>() = v.cast<Real>();  // now the velocity
  };

  const std::size_t node_chunks = ChunkCount(nodes);
  work.grid_chunks.assign(node_chunks, GridTotals{});
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(node_chunks); ++c) {
    GridTotals& totals = work.grid_chunks[c];
    const std::size_t end = std::min(nodes, (c + 1) * kChunk);
    for (std::size_t node = c * kChunk; node < end; ++node) {
      const int k = static_cast<int>(node % grid.dims.z());
      const int j = static_cast<int>((node / grid.dims.z()) % grid.dims.y());
      const int i = static_cast<int>(node / (static_cast<std::size_t>(grid.dims.y()) * grid.dims.z()));
      const Eigen::Vector3d x = node_position(i, j, k);
      update_node(x, &grid.node[node], -1, &totals);
      const std::int32_t slot = split_on ? grid.split_slot[node] : -1;
      if (slot >= 0) {
        for (int side = 0; side < 2; ++side) {
          update_node(x, &grid.layer[side][slot], side, &totals);
        }
      }
    }
  }
  const GridTotals grid_totals = SumChunks(work.grid_chunks);
  const double c_norm = kContactStrengthScale * dx / dt_s;
  // The number of nodes along the edge grows as 1 / dx: scale the sum back to the reference grid.
  const double approach_sum_m_s =
      grid_totals.approach_speed_sum * (dx / cutting.band_reference_dx_m);
  const double c_hat = knife_on ? std::min(1.0, approach_sum_m_s / c_norm) : 0.0;
  const Eigen::Vector3d knife_velocity =
      knife_on ? knife_->motion().linear_velocity_m_s : Eigen::Vector3d::Zero();
  // Damage needs the edge moving edge-first into the food (a downward stroke).
  const bool downward_stroke =
      knife_on && knife_velocity.dot(knife_->motion().pose.linear().col(2)) > 0.0;
  const bool damage_gate =
      knife_on && effects.damage && c_hat >= cutting.c_hat_min && downward_stroke;
  const bool tip_on = knife_on && cutting.tip_acceleration_m_s2 > 0.0;
  const Eigen::AlignedBox3d damage_box = knife_on ? knife_->BladeBounds(band_m) : Eigen::AlignedBox3d();

  diagnostics.grid_ms = elapsed_ms(stage_start);
  stage_start = Clock::now();

  // --- G2P: velocity and affine field back, F update with J clamp, damage, tip force --------
  const std::size_t particle_chunks = ChunkCount(n);
  work.particle_chunks.assign(particle_chunks, ParticleTotals{});
  const Real c_scale = Real(4) * inv_dx * inv_dx;
  const Real j_min = Real(config_.j_min);
  const Real j_max = Real(config_.j_max);
  const Real max_speed = Real(config_.max_particle_speed_m_s);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(particle_chunks); ++c) {
    ParticleTotals& totals = work.particle_chunks[c];
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    for (std::size_t s = c * kChunk; s < end; ++s) {
      const std::uint32_t q = work.order[s];
      const Stencil<Real> stencil = StencilOf(p, q, inv_dx, grid.origin);
      const int* base = stencil.base;
      const Real* fx = stencil.fx;
      const auto& w = stencil.w;
      const int side = p.blade_side[q] > 0 ? 1 : 0;
      const bool near_split = split_on && block_near_split[block_of[q]];
      // v = sum w v_i; B = sum w v_i (x_i - x_p)^T = sum w v_i (ijk dx)^T - v (fx dx)^T, with the
      // first sum kept per axis index.
      Vector4<Real> v4 = Vector4<Real>::Zero();
      Vector4<Real> by_i[3] = {Vector4<Real>::Zero(), Vector4<Real>::Zero(), Vector4<Real>::Zero()};
      Vector4<Real> by_j[3] = {Vector4<Real>::Zero(), Vector4<Real>::Zero(), Vector4<Real>::Zero()};
      Vector4<Real> by_k[3] = {Vector4<Real>::Zero(), Vector4<Real>::Zero(), Vector4<Real>::Zero()};
      const std::size_t stride_i = static_cast<std::size_t>(grid.dims.y()) * grid.dims.z();
      const std::size_t stride_j = grid.dims.z();
      const std::size_t origin_node = grid.Index(base[0], base[1], base[2]);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const Real weight_ij = w[0][i] * w[1][j];
          const std::size_t row = origin_node + i * stride_i + j * stride_j;
          for (int k = 0; k < 3; ++k) {
            const std::size_t node = row + k;
            const std::int32_t slot = near_split ? grid.split_slot[node] : -1;
            const GridNode<Real>& source = slot >= 0 ? grid.layer[side][slot] : grid.node[node];
            const Vector4<Real> weighted = (weight_ij * w[2][k]) * source;  // lane 3 unused
            v4 += weighted;
            by_i[i] += weighted;
            by_j[j] += weighted;
            by_k[k] += weighted;
          }
        }
      }
      Vector3<Real> v = v4.template head<3>();
      Matrix3<Real> B;
      B.col(0) = ((by_i[1] + Real(2) * by_i[2]).template head<3>() - fx[0] * v) * dx_r;
      B.col(1) = ((by_j[1] + Real(2) * by_j[2]).template head<3>() - fx[1] * v) * dx_r;
      B.col(2) = ((by_k[1] + Real(2) * by_k[2]).template head<3>() - fx[2] * v) * dx_r;
      const Matrix3<Real> C = c_scale * B;
      const Eigen::Vector3d x(p.position[0][q], p.position[1][q], p.position[2][q]);

      // Damage where the edge presses into the food fast enough (paper: gated by c-hat, the
      // approach speed and the stroke direction, inside the blade band).
      if (damage_gate && p.damage[q] < Real(1) && damage_box.contains(x) &&
          knife_->HeightAboveEdge(x) < band_m) {
        // Only at the edge: the flat faces push the cut sides apart but do not cut them.
        const SdfSample sample = knife_->Blade(x);
        if (std::abs(sample.distance_m) < band_m) {
          // The velocity it came in with: contact has already removed the approach from v.
          const Eigen::Vector3d v_start(p.velocity[0][q], p.velocity[1][q], p.velocity[2][q]);
          const Eigen::Vector3d relative = v_start - knife_->motion().VelocityAt(x);
          const double normal_speed = relative.dot(sample.normal);
          if (normal_speed <= -v_threshold_m_s) {
            const double increment = cutting.damage_per_band * (-normal_speed * dt_s) / band_m;
            p.damage[q] = std::min(Real(1), p.damage[q] + Real(increment));
            ++totals.damaged;
          }
        }
      }
      // Tip force: push labelled particles near the edge away from the blade plane.
      if (tip_on && p.blade_side[q] != 0 && damage_box.contains(x) &&
          std::abs(knife_->HeightAboveEdge(x)) < cutting.tip_band_cells * dx &&
          knife_->WithinBladeLength(x)) {
        const Eigen::Vector3d push =
            (p.blade_side[q] > 0 ? 1.0 : -1.0) * cutting.tip_acceleration_m_s2 * dt_s * blade_normal;
        v += push.cast<Real>();
        totals.particle_impulse += double(p.mass[q]) * push;
      }
      const Real speed = v.norm();
      if (speed > max_speed) {
        const Vector3<Real> uncapped = v;
        v *= max_speed / speed;
        ++totals.speed_caps;
        totals.particle_impulse += double(p.mass[q]) * (v - uncapped).template cast<double>();
      }
      for (int axis = 0; axis < 3; ++axis) {
        p.velocity[axis][q] = v[axis];
        p.position[axis][q] += dt * v[axis];
      }
      for (int k = 0; k < 9; ++k) p.C[k][q] = C(k / 3, k % 3);

      // F <- (I + dt C) F (paper eq. Fupdate), then J clamped isotropically to [j_min, j_max].
      Matrix3<Real> F;
      for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
      F = (Matrix3<Real>::Identity() + dt * C) * F;
      Real J = F.determinant();
      if (!(J >= j_min && J <= j_max)) {
        const Real target = std::isfinite(J) && J > Real(0) ? std::clamp(J, j_min, j_max) : Real(1);
        F = std::isfinite(J) && J > Real(0) ? Matrix3<Real>(F * std::cbrt(target / J))
                                             : Matrix3<Real>::Identity();
        J = F.determinant();  // what the clamp achieved, not what it aimed at
        ++totals.j_clamps;
      }
      for (int k = 0; k < 9; ++k) p.F[k][q] = F(k / 3, k % 3);
      totals.j_min = std::min(totals.j_min, double(J));
      totals.j_max = std::max(totals.j_max, double(J));
      const double m = p.mass[q];
      for (int axis = 0; axis < 3; ++axis) totals.momentum[axis] += m * v[axis];
      totals.kinetic_energy += 0.5 * m * double(v.squaredNorm());
    }
  }
  ParticleTotals particle_totals = SumChunks(work.particle_chunks);
  for (double energy : elastic_energy_of_chunk) particle_totals.elastic_energy += energy;

  diagnostics.g2p_ms = elapsed_ms(stage_start);

  // --- Diagnostics ---------------------------------------------------------------------------
  diagnostics.j_min = particle_totals.j_min;
  diagnostics.j_max = particle_totals.j_max;
  diagnostics.j_clamps = particle_totals.j_clamps;
  diagnostics.speed_caps = particle_totals.speed_caps + grid_totals.speed_caps;
  diagnostics.damaged_particles = particle_totals.damaged;
  diagnostics.kinetic_energy_j = particle_totals.kinetic_energy;
  diagnostics.elastic_energy_j = particle_totals.elastic_energy;
  diagnostics.c_hat = c_hat;
  diagnostics.knife_velocity_m_s = knife_velocity;
  if (effects.force_sensing) {
    // The food pushes each collider with minus the impulse the collider gave it (paper eq. force).
    diagnostics.force_on_blade_n = -grid_totals.blade_impulse / dt_s;
    diagnostics.force_on_handle_n = -grid_totals.handle_impulse / dt_s;
    diagnostics.force_on_board_n = -grid_totals.board_impulse / dt_s;
    diagnostics.force_on_table_n = -grid_totals.table_impulse / dt_s;
    const Eigen::Vector3d collider_impulse = grid_totals.blade_impulse + grid_totals.handle_impulse +
                                             grid_totals.board_impulse + grid_totals.table_impulse;
    diagnostics.momentum_change_n_s = particle_totals.momentum - momentum_before;
    diagnostics.external_impulse_n_s =
        collider_impulse + grid_totals.other_impulse + particle_totals.particle_impulse;
    // Relative to the larger of the contact impulse and the food's weight over the substep.
    const double scale = std::max(collider_impulse.norm(),
                                  grid_totals.mass * config_.gravity_m_s2.norm() * dt_s);
    diagnostics.momentum_residual =
        scale > 0.0
            ? (diagnostics.momentum_change_n_s - diagnostics.external_impulse_n_s).norm() / scale
            : 0.0;
  }
  // Quadratic speed resistance (paper): u <- u / (1 + k2 c-hat u dt) with u = 1 the current speed;
  // k2 grows with the material's stiffness and strength.
  if (knife_on && c_hat > 0.0) {
    const Material& material = materials_.front();
    const double k2 = cutting.k2_reference_per_s *
                      (material.youngs_modulus_pa / cutting.k2_reference_youngs_pa) *
                      (1.0 + material.yield_stress_pa / cutting.k2_reference_yield_pa);
    diagnostics.knife_speed_factor = 1.0 / (1.0 + k2 * c_hat * dt_s);
  }
  return diagnostics;
}

template class Solver<float>;
template class Solver<double>;

}  // namespace culinarycut::mpm
