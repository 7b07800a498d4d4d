// Grid update: momentum to velocity, gravity, damping, then each collider within its bounding box
// (board, table, blade, the blade faces for split layers, handle), with every velocity change a
// collider makes summed as its impulse; and the contact strength c-hat the cut depends on.
#include <algorithm>
#include <cmath>

#include "sim/mpm/kernels/solver_internals.h"
#include "sim/mpm/physics/edge_resistance.h"
#include "sim/mpm/physics/grid_contact.h"

namespace culinarycut::mpm {
namespace {

// Without the two-sided blade, unsplit nodes feel the blade within half a cell of its surface: a
// thin blade between two node layers would otherwise never touch them and the food would leak
// through. With it, the split layers see the faces and the edge nodes the edge: no offset.
constexpr double kUnsplitBladeOffsetCells = 0.5;
// A split layer sees the blade's face when its node is within half a cell of it: the food's nearest
// node layer on each side then always touches the face, wherever the blade lies between nodes.
constexpr double kFaceReachCells = 0.5;

}  // namespace

// Team: every thread calls it and, after the barrier that ends the node loop, sums the chunks
// into its own `contact` (the same bits on every thread: no single and no second barrier).
template <typename Real>
void Solver<Real>::UpdateGrid(const SubstepContext& context, ContactState* contact_out) {
  Grid& grid = *grid_;
  Workspace& work = *workspace_;
  const Effects& effects = config().effects;
  const CuttingParameters& cutting = config().cutting;
  const double dt_s = context.dt_s;
  const double dx = context.dx_m;
  const bool knife_on = context.knife_on;
  const bool split_on = context.split_on;
  const double blade_half_m = context.blade_half_m;
  const std::size_t nodes = grid.size();
  const ContactMaterials& contact_materials = work.contact_materials;
  const bool use_friction = effects.friction;
  const Eigen::AlignedBox3d blade_box =
      knife_on ? knife_->BladeBounds(kEdgeReachCells * dx) : Eigen::AlignedBox3d();
  const Eigen::AlignedBox3d handle_box =
      knife_on ? knife_->HandleBounds(dx) : Eigen::AlignedBox3d();
  const Eigen::AlignedBox3d board_box = board_ ? board_->Bounds(dx) : Eigen::AlignedBox3d();
  const double damping = 1.0 / (1.0 + config().grid_damping_per_s * dt_s);
  const Eigen::Vector3d blade_normal =
      knife_on ? Eigen::Vector3d(knife_->motion().pose.linear().col(1)) : Eigen::Vector3d::UnitY();
  // The direction the edge cuts in (TCP z: from the edge into the food below it).
  const Eigen::Vector3d cutting_direction =
      knife_on ? Eigen::Vector3d(knife_->motion().pose.linear().col(2)) : Eigen::Vector3d::UnitZ();
  const double half_length_m = context.half_length_m;
  const double blade_offset_m = split_on ? 0.0 : kUnsplitBladeOffsetCells * dx;

  const Eigen::Vector3d gravity = config().weight_acceleration_m_s2();
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
    const Eigen::Vector3d v_undamped = v + dt_s * gravity;
    v = v_undamped * damping;
    if (sense_force) {
      totals->other_impulse += m * dt_s * gravity + m * (v - v_undamped);
      totals->mass += m;
    }
    double approach = 0.0;
    // The food this node belongs to (its friction and resistance), looked up only on contact.
    const ContactMaterial* food = nullptr;
    auto food_at_node = [&]() -> const ContactMaterial& {
      if (!food) food = &contact_materials.At(x);
      return *food;
    };
    // Most nodes in the board's bounding box lie on top of it: a cheap inside test first.
    if (board_ && board_box.contains(x) && board_->Contains(x)) {
      const SdfSample sample = board_->Sample(x);
      const Eigen::Vector3d before = v;
      if (ResolveContact(sample.normal, board_->motion().VelocityAt(x), food_at_node().board_friction,
                         use_friction, &v, &approach)) {
        if (sense_force) totals->board_impulse += m * (v - before);
      }
    }
    if (table_ && x.z() <= table_->height_m()) {
      const Eigen::Vector3d before = v;
      if (ResolveContact(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), food_at_node().board_friction,
                         use_friction, &v, &approach)) {
        if (sense_force) totals->table_impulse += m * (v - before);
      }
    }
    if (knife_on) {
      if (side >= 0) {
        // The blade face on this side: material of this side may not move through it.
        const double sign = side == 1 ? 1.0 : -1.0;
        if (sign * knife_->SideOfBlade(x) < blade_half_m + kFaceReachCells * dx) {
          const Eigen::Vector3d before = v;
          if (ResolveContact(sign * blade_normal, knife_->motion().VelocityAt(x), food_at_node().knife_friction,
                             use_friction, &v, &approach)) {
            if (sense_force) totals->blade_impulse += m * (v - before);
          }
        }
      } else if (blade_box.contains(x)) {
        const Eigen::Vector3d local = knife_->ToTcpFrame(x);
        const double height_m = -local.z();
        // The node a cell above is split (so this one carries its column's share of the edge).
        const bool above_is_split = split_on && height_m + dx >= kSplitAboveEdgeCells * dx;
        const double share = std::abs(local.x()) <= half_length_m
                                 ? EdgeShare(local.y(), height_m, dx, above_is_split)
                                 : 0.0;
        if (share > 0.0) {
          // The edge pushes the food ahead of it with at most its share of G_c L (edge_resistance.h).
          const Eigen::Vector3d before = v;
          const Eigen::Vector3d knife_velocity = knife_->motion().VelocityAt(x);
          if (ResolveContact(cutting_direction, knife_velocity, food_at_node().knife_friction, use_friction, &v,
                             &approach)) {
            const ContactMaterial& food_here = food_at_node();
            const double fill = EdgeFill(m, food_here.density_kg_m3, dx);
            CapImpulse(before, m, EdgeImpulseCap(share, food_here.toughness_j_m2, fill, dx, dt_s), &v);
            if (sense_force) {
              totals->blade_impulse += m * (v - before);
              totals->edge_impulse += m * (v - before);
            }
            totals->approach_speed_sum += approach;
            // The edge length this node stands for times the edge's own speed into the food: unlike the
            // approach speed, neither grows with the substep (the speed resistance's contact strength).
            const double sweep_m2_s =
                share * fill * dx * std::max(0.0, knife_velocity.dot(cutting_direction));
            totals->edge_sweep_m2_s += sweep_m2_s;
            totals->resistance_sum += sweep_m2_s * food_here.k2_per_s;
            totals->wave_speed_sum += sweep_m2_s * food_here.wave_speed_m_s;
          }
        } else {
          const SdfSample sample = knife_->Blade(x);
          if (sample.distance_m < blade_offset_m) {
            const Eigen::Vector3d before = v;
            if (ResolveContact(sample.normal, knife_->motion().VelocityAt(x), food_at_node().knife_friction,
                               use_friction, &v, &approach)) {
              if (sense_force) totals->blade_impulse += m * (v - before);
            }
          }
        }
      }
      if (handle_box.contains(x)) {
        const SdfSample sample = knife_->Handle(x);
        if (sample.distance_m < 0.0) {
          const Eigen::Vector3d before = v;
          if (ResolveContact(sample.normal, knife_->motion().VelocityAt(x), food_at_node().knife_friction,
                             use_friction, &v, &approach)) {
            if (sense_force) totals->handle_impulse += m * (v - before);
          }
        }
      }
    }
    const double speed = v.norm();
    if (speed > config().max_grid_speed_m_s) {
      const Eigen::Vector3d uncapped = v;
      v *= config().max_grid_speed_m_s / speed;
      ++totals->speed_caps;
      if (sense_force) totals->other_impulse += m * (v - uncapped);
    }
    grid_node->template head<3>() = v.cast<Real>();  // now the velocity
  };

  const std::size_t node_chunks = ChunkCount(nodes);  // work.grid_chunks: zeroed with the grid box
  const std::size_t stride_i = grid.stride_i();
  const std::size_t stride_j = grid.stride_j();
#pragma omp for schedule(dynamic, 1)
  for (std::int64_t c = 0; c < static_cast<std::int64_t>(node_chunks); ++c) {
    GridTotals& totals = work.grid_chunks[c];
    const std::size_t end = std::min(nodes, (c + 1) * kChunk);
    for (std::size_t node = c * kChunk; node < end; ++node) {
      const std::int32_t slot = split_on ? grid.split_slot[node] : -1;
      // Empty nodes (most of the box's margin) need no position and no collider query.
      if (grid.node[node][3] <= Real(0) && slot < 0) continue;
      const int i = static_cast<int>(node / stride_i);
      const int j = static_cast<int>((node % stride_i) / stride_j);
      const int k = static_cast<int>(node % stride_j);
      const Eigen::Vector3d x = grid.Position(i, j, k, dx);
      update_node(x, &grid.node[node], -1, &totals);
      if (slot >= 0) {
        for (int side = 0; side < 2; ++side) {
          update_node(x, &grid.layer[side][slot], side, &totals);
        }
      }
    }
  }
  {
  ContactState& contact = *contact_out;
  contact.totals = SumChunks(work.grid_chunks);
  const double c_norm = kContactStrengthScale * dx / dt_s;
  // The number of nodes along the edge grows as 1 / dx: scale the sum back to the reference grid.
  const double approach_sum_m_s =
      contact.totals.approach_speed_sum * (dx / cutting.band_reference_dx_m);
  contact.c_hat = knife_on ? std::min(1.0, approach_sum_m_s / c_norm) : 0.0;
  // Damage needs the edge moving edge-first into the food (a downward stroke).
  const bool downward_stroke =
      knife_on && knife_->motion().linear_velocity_m_s.dot(knife_->motion().pose.linear().col(2)) > 0.0;
  contact.damage_gate =
      knife_on && effects.damage && contact.c_hat >= cutting.c_hat_min && downward_stroke;
  contact.tip_on = knife_on && cutting.tip_acceleration_m_s2 > 0.0;
  }
}

template void Solver<float>::UpdateGrid(const SubstepContext&, ContactState*);
template void Solver<double>::UpdateGrid(const SubstepContext&, ContactState*);

}  // namespace culinarycut::mpm
