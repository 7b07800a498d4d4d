#include "tools/cc_cut/cut_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "sim/core/stage_timer.h"
#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {
namespace {

// The knife TCP frame for a blade across `axis` (horizontal, unit): blade normal (TCP y) along the
// axis, edge down (TCP z = -world z), TCP x = y cross z along the blade. Yaw 0 gives BladeAcrossX.
Eigen::Matrix3d BladeAcross(const Eigen::Vector3d& axis) {
  Eigen::Matrix3d rotation;
  rotation.col(1) = axis;
  rotation.col(2) = -Eigen::Vector3d::UnitZ();
  rotation.col(0) = rotation.col(1).cross(rotation.col(2));
  return rotation;
}

// Where the knife is in its path and how fast it moves.
struct KnifeState {
  enum class Phase { kDescending, kLifting, kSettling };
  Phase phase = Phase::kDescending;
  double height_m = 0.0;
  double speed_fraction = 1.0;  // descent speed / descent_speed_m_s
  double settle_left_s = 0.0;
};

}  // namespace

CutSceneSummary RunCutScene(const CutScene& scene, const CutStepCallback& on_step) {
  const auto start_total = std::chrono::steady_clock::now();
  CutSceneSummary summary;
  summary.material = ResolveMaterial(scene);
  Solver<float> solver(scene.solver, {summary.material});
  const double dx = scene.solver.dx_m;
  const CutSceneKnife& path = scene.knife;

  // The food, resting on the board unless its height is given.
  const auto shape = MakeFoodShape(scene.food.name, scene.food.scale);
  const Eigen::AlignedBox3d local = shape->LocalBounds();
  const double board_top_m = summary.board_centre_m.z() + 0.5 * summary.board_size_m.z();
  const double yaw_rad = scene.food.yaw_deg * M_PI / 180.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() =
      Eigen::Vector3d(scene.food.position_xy_m.x(), scene.food.position_xy_m.y(),
                      scene.food.position_z_m.value_or(board_top_m - local.min().z()));
  SamplingOptions sampling;
  sampling.dx_m = dx;
  sampling.particles_per_cell = scene.particles_per_cell;
  sampling.seed = scene.seed;
  const auto start_sampling = std::chrono::steady_clock::now();
  summary.particles =
      SampleFood(*shape, pose, summary.material.density_kg_m3, 0, 0, sampling, &solver.particles());
  summary.sampling_ms = MillisecondsSince(start_sampling);
  if (summary.particles == 0) {
    throw std::invalid_argument("solver.dx_m: no particle sampled; the food is too small for dx");
  }

  RigidMotion board;
  board.pose.translation() = summary.board_centre_m;
  solver.SetBoard(summary.board_size_m, board);
  solver.SetTable(summary.table_height_m);
  solver.SetKnife(KnifeGeometry{});

  // The long axis and the path.
  const Eigen::Vector3d axis = pose.linear().col(0);
  const Eigen::Vector3d centre = pose.translation();
  summary.food_length_m = local.sizes().x();
  summary.axis_direction = axis;
  summary.axis_origin_m = centre + local.min().x() * axis;
  const double cut_local_x_m = path.cut_local_x_m.value_or(
      local.min().x() + path.cut_fraction.value_or(0.5) * summary.food_length_m);
  summary.requested_cut_m = cut_local_x_m - local.min().x();
  const Eigen::Vector3d cut_point = centre + cut_local_x_m * axis;
  const double food_top_m = centre.z() + local.max().z();
  const double food_bottom_m = centre.z() + local.min().z();
  summary.start_height_m = food_top_m + path.start_above_top_m;
  summary.end_height_m = food_bottom_m - path.end_below_bottom_m;
  const Eigen::Matrix3d blade_rotation = BladeAcross(axis);
  const Eigen::Vector3d along_blade = blade_rotation.col(0);

  summary.dt_s = solver.StableTimestep();
  const double dt = summary.dt_s;
  KnifeState knife;
  knife.height_m = summary.start_height_m;
  knife.settle_left_s = path.settle_s;
  double collider_impulse_sum = 0.0;
  double time_s = 0.0;
  double substep_ms = 0.0;
  while (true) {
    if (time_s >= path.max_time_s) {
      summary.hit_time_limit = true;
      break;
    }
    const bool descending = knife.phase == KnifeState::Phase::kDescending;
    const double phase_rad = 2.0 * M_PI * path.saw_frequency_hz * time_s;
    const double saw_m = descending ? path.saw_amplitude_m * std::sin(phase_rad) : 0.0;
    const double saw_m_s =
        descending ? path.saw_amplitude_m * 2.0 * M_PI * path.saw_frequency_hz * std::cos(phase_rad)
                   : 0.0;
    double vz_m_s = 0.0;
    if (descending) vz_m_s = -path.descent_speed_m_s * knife.speed_fraction;
    if (knife.phase == KnifeState::Phase::kLifting) vz_m_s = path.lift_speed_m_s;
    RigidMotion motion;
    motion.pose.linear() = blade_rotation;
    motion.pose.translation() =
        Eigen::Vector3d(cut_point.x(), cut_point.y(), knife.height_m) + saw_m * along_blade;
    motion.linear_velocity_m_s = saw_m_s * along_blade + Eigen::Vector3d(0.0, 0.0, vz_m_s);
    solver.SetKnifeMotion(motion);

    CutStepRecord record;
    record.step = summary.substeps;
    record.knife_height_m = knife.height_m;
    record.diagnostics = solver.Substep(dt);
    const SubstepDiagnostics& d = record.diagnostics;
    time_s += dt;
    record.time_s = time_s;
    ++summary.substeps;

    // Totals.
    substep_ms += d.setup_ms + d.p2g_ms + d.grid_ms + d.g2p_ms;
    summary.setup_ms += d.setup_ms;
    summary.p2g_ms += d.p2g_ms;
    summary.grid_ms += d.grid_ms;
    summary.g2p_ms += d.g2p_ms;
    const double blade_force_n = d.force_on_blade_n.norm();
    if (blade_force_n > summary.peak_blade_force_n) {
      summary.peak_blade_force_n = blade_force_n;
      summary.peak_blade_force_time_s = time_s;
    }
    summary.blade_impulse_n_s += d.force_on_blade_n * dt;
    summary.external_impulse_n_s += d.external_impulse_n_s;
    summary.momentum_change_n_s += d.momentum_change_n_s;
    collider_impulse_sum += (d.force_on_blade_n.norm() + d.force_on_handle_n.norm() +
                             d.force_on_board_n.norm() + d.force_on_table_n.norm()) *
                            dt;
    summary.worst_momentum_residual =
        std::max(summary.worst_momentum_residual, d.momentum_residual);
    summary.j_min = std::min(summary.j_min, d.j_min);
    summary.j_max = std::max(summary.j_max, d.j_max);
    summary.j_clamps += d.j_clamps;
    summary.speed_caps += d.speed_caps;
    if (on_step) on_step(record);

    // Advance the knife along its path.
    if (knife.phase == KnifeState::Phase::kDescending) {
      knife.height_m += vz_m_s * dt;
      if (path.apply_speed_resistance && d.knife_speed_factor < 1.0) {
        // The solver's factor is 1 / (1 + k c u dt) at u = 1; apply it at the current speed u.
        const double k_c_dt = 1.0 / d.knife_speed_factor - 1.0;
        knife.speed_fraction = std::max(
            path.min_speed_fraction, knife.speed_fraction / (1.0 + k_c_dt * knife.speed_fraction));
        summary.min_speed_factor = std::min(summary.min_speed_factor, knife.speed_fraction);
      }
      if (knife.height_m <= summary.end_height_m) knife.phase = KnifeState::Phase::kLifting;
    } else if (knife.phase == KnifeState::Phase::kLifting) {
      knife.height_m = std::min(summary.start_height_m, knife.height_m + vz_m_s * dt);
      if (knife.height_m >= summary.start_height_m) knife.phase = KnifeState::Phase::kSettling;
    } else {
      knife.settle_left_s -= dt;
      if (knife.settle_left_s <= 0.0) break;
    }
  }
  summary.sim_time_s = time_s;
  const Eigen::Vector3d mismatch = summary.momentum_change_n_s - summary.external_impulse_n_s;
  summary.momentum_mismatch =
      collider_impulse_sum > 0.0 ? mismatch.norm() / collider_impulse_sum : 0.0;

  // Pieces: damage alone separates them.
  const auto start_topology = std::chrono::steady_clock::now();
  summary.topology.link_distance_m = 0.75 * dx;
  summary.topology.min_piece_particles = 20;
  summary.topology.separate_blade_sides = false;
  summary.pieces = DetectPieces(summary.topology, &solver.particles());
  summary.cut_positions_m =
      CutPositionsAlongAxis(summary.pieces, 0, summary.axis_origin_m, summary.axis_direction);
  for (const auto damage : solver.particles().damage) {
    summary.broken_particles += damage >= summary.topology.broken_damage;
  }
  summary.topology_ms = MillisecondsSince(start_topology);
  summary.total_ms = MillisecondsSince(start_total);
  if (substep_ms > 0.0) {
    summary.particle_steps_per_s =
        double(summary.particles) * summary.substeps / (substep_ms * 1e-3);
  }
  return summary;
}

}  // namespace culinarycut::mpm
