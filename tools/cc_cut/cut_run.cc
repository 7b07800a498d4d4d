#include "tools/cc_cut/cut_run.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <fstream>
#include <string>

#include "sim/core/stage_timer.h"
#include "sim/mpm/physics/speed_resistance.h"
#include "sim/task/object_box.h"
#include "sim/world/food_state.h"

namespace culinarycut::cc_cut {
namespace {

// The knife TCP frame for a blade across `axis` (unit): blade normal (TCP y) along the axis's
// horizontal part, edge down (TCP z = -world z), TCP x = y cross z along the blade.
Eigen::Matrix3d BladeAcross(const Eigen::Vector3d& axis) {
  Eigen::Matrix3d rotation;
  rotation.col(1) = Eigen::Vector3d(axis.x(), axis.y(), 0.0).normalized();
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

// The food's long axis, the requested cut point and the path's edge heights.
void ResolvePath(const CutModel& model, CutSummary* summary) {
  const task::ObjectBox& food = model.food.objects.front();
  const task::LongAxis axis = task::LongAxisOf(food);
  const KnifePath& path = model.knife;
  summary->food_length_m = axis.length_m;
  summary->axis_origin_m = axis.left_end_m;
  summary->axis_direction = axis.direction;
  summary->requested_cut_m = path.cut_from_centre_m
                                 ? 0.5 * axis.length_m + *path.cut_from_centre_m
                                 : path.cut_fraction.value_or(0.5) * axis.length_m;
  summary->start_height_m = task::TopZ(food) + path.start_above_top_m;
  summary->end_height_m = task::BottomZ(food) - path.end_below_bottom_m;
}

// This process's peak resident memory (MB): VmHWM of /proc/self/status, which, unlike getrusage's
// maxrss, does not carry the parent's memory over the fork and exec that started us. 0 off Linux.
double PeakResidentMegabytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  }
  return 0.0;
}

}  // namespace

CutSummary RunCut(const CutModel& model, const CutStepCallback& on_step) {
  const auto start_total = std::chrono::steady_clock::now();
  CutSummary summary;
  summary.compile_ms = model.compile_ms;
  summary.material = model.food.solver->materials.front();
  summary.particles = model.food.initial_particles.size();
  ResolvePath(model, &summary);
  const KnifePath& path = model.knife;

  // The food, board, table and knife exactly as a server episode starts them.
  FoodState food;
  ResetFood(model.food, model.layout, &food);
  mpm::Solver<float>& solver = *food.solver;

  const Eigen::Vector3d cut_point =
      summary.axis_origin_m + summary.requested_cut_m * summary.axis_direction;
  const Eigen::Matrix3d blade_rotation = BladeAcross(summary.axis_direction);
  const Eigen::Vector3d along_blade = blade_rotation.col(0);

  // Short enough for the fastest the knife goes (descending, lifting or sawing) as well as for sound.
  const double fastest_knife_m_s = std::max({path.descent_speed_m_s, path.lift_speed_m_s,
                                             2.0 * M_PI * path.saw_frequency_hz * path.saw_amplitude_m});
  summary.dt_s = mpm::StableTimestep(*model.food.solver, fastest_knife_m_s);
  summary.min_dt_s = summary.dt_s;
  // ... and for the fastest particle, from the substep before (a scan for the first).
  double fastest_particle_m_s = mpm::FastestParticleSpeed(solver.particles());
  KnifeState knife;
  knife.height_m = summary.start_height_m;
  knife.settle_left_s = path.settle_s;
  double collider_impulse_sum = 0.0;
  double kinetic_in_contact_j_s = 0.0;  // energies integrated over the substeps with blade contact
  double elastic_in_contact_j_s = 0.0;
  std::deque<std::pair<double, Eigen::Vector3d>> window;  // (dt, blade impulse) of the last substeps
  Eigen::Vector3d window_impulse_n_s = Eigen::Vector3d::Zero();
  double window_s = 0.0;
  double time_s = 0.0;
  double substep_ms = 0.0;
  double active_particle_steps = 0.0;  // sum over substeps of the particles integrated
  while (true) {
    if (time_s >= path.max_time_s) {
      summary.hit_time_limit = true;
      break;
    }
    const double dt = mpm::StableTimestep(*model.food.solver, fastest_knife_m_s, fastest_particle_m_s);
    summary.min_dt_s = std::min(summary.min_dt_s, dt);
    const bool descending = knife.phase == KnifeState::Phase::kDescending;
    const double phase_rad = 2.0 * M_PI * path.saw_frequency_hz * time_s;
    const double saw_m = descending ? path.saw_amplitude_m * std::sin(phase_rad) : 0.0;
    const double saw_m_s =
        descending ? path.saw_amplitude_m * 2.0 * M_PI * path.saw_frequency_hz * std::cos(phase_rad)
                   : 0.0;
    double vz_m_s = 0.0;
    if (descending) vz_m_s = -path.descent_speed_m_s * knife.speed_fraction;
    if (knife.phase == KnifeState::Phase::kLifting) vz_m_s = path.lift_speed_m_s;
    mpm::RigidMotion motion;
    motion.pose.linear() = blade_rotation;
    motion.pose.translation() =
        Eigen::Vector3d(cut_point.x(), cut_point.y(), knife.height_m) + saw_m * along_blade;
    motion.linear_velocity_m_s = saw_m_s * along_blade + Eigen::Vector3d(0.0, 0.0, vz_m_s);
    solver.SetKnifeMotion(motion);

    CutStepRecord record;
    record.step = summary.substeps;
    record.knife_height_m = knife.height_m;
    record.diagnostics = solver.Substep(dt);
    const mpm::SubstepDiagnostics& d = record.diagnostics;
    fastest_particle_m_s = d.fastest_particle_m_s;
    time_s += dt;
    record.time_s = time_s;
    ++summary.substeps;

    // Totals.
    substep_ms += d.setup_ms + d.p2g_ms + d.grid_ms + d.g2p_ms;
    summary.setup_ms += d.setup_ms;
    summary.p2g_ms += d.p2g_ms;
    summary.grid_ms += d.grid_ms;
    summary.g2p_ms += d.g2p_ms;
    // The force over the accumulation window: the blade's impulse over the last window / the window.
    window.push_back({dt, d.force_on_blade_n * dt});
    window_impulse_n_s += d.force_on_blade_n * dt;
    window_s += dt;
    while (window.size() > 1 && window_s - window.front().first >= path.force_window_s) {
      window_s -= window.front().first;
      window_impulse_n_s -= window.front().second;
      window.pop_front();
    }
    const double windowed_force_n = window_impulse_n_s.norm() / window_s;  // the first window: so far
    if (windowed_force_n > summary.peak_blade_force_n) {
      summary.peak_blade_force_n = windowed_force_n;
      summary.peak_blade_force_time_s = time_s;
    }
    summary.peak_substep_blade_force_n = std::max(summary.peak_substep_blade_force_n, d.force_on_blade_n.norm());
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
    active_particle_steps += static_cast<double>(d.active_particles);
    if (d.force_on_blade_n.squaredNorm() > 0.0) {
      kinetic_in_contact_j_s += d.kinetic_energy_j * dt;
      elastic_in_contact_j_s += d.elastic_energy_j * dt;
    }
    if (on_step) on_step(record);

    // Advance the knife along its path.
    if (knife.phase == KnifeState::Phase::kDescending) {
      knife.height_m += vz_m_s * dt;
      if (path.apply_speed_resistance && d.knife_speed_factor < 1.0) {
        // The same model and units (m/s) as the world's.
        const double speed_m_s = path.descent_speed_m_s * knife.speed_fraction;
        knife.speed_fraction = std::max(
            path.min_speed_fraction,
            knife.speed_fraction * mpm::SpeedResistanceFactor(speed_m_s, mpm::SubstepResistance(d)));
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
  if (summary.substeps > 0 && summary.particles > 0) {
    summary.active_particle_fraction =
        active_particle_steps / (static_cast<double>(summary.substeps) * static_cast<double>(summary.particles));
  }
  if (elastic_in_contact_j_s > 0.0) summary.kinetic_to_elastic_energy = kinetic_in_contact_j_s / elastic_in_contact_j_s;
  const Eigen::Vector3d mismatch = summary.momentum_change_n_s - summary.external_impulse_n_s;
  summary.momentum_mismatch =
      collider_impulse_sum > 0.0 ? mismatch.norm() / collider_impulse_sum : 0.0;

  // Pieces, with the topology options a server session uses (damage alone separates them).
  const auto start_topology = std::chrono::steady_clock::now();
  UpdatePieces(model.food, &food);
  summary.pieces = food.pieces;
  // The particles carry the scaled inertia (mass scaling); a piece's mass is the food's real one.
  for (mpm::Piece& piece : summary.pieces) piece.mass_kg /= model.food.solver->config.mass_scaling;
  summary.cut_positions_m =
      mpm::CutPositionsAlongAxis(summary.pieces, 0, summary.axis_origin_m, summary.axis_direction);
  const mpm::Particles<float>& particles = solver.particles();
  for (int axis = 0; axis < 3; ++axis) {
    summary.final_particles.rest_position_m[axis] = particles.rest_position[axis];
    summary.final_particles.position_m[axis] = particles.position[axis];
  }
  summary.final_particles.piece = particles.piece;
  for (const auto damage : solver.particles().damage) {
    summary.broken_particles += damage >= model.food.topology.broken_damage;
  }
  summary.topology_ms = MillisecondsSince(start_topology);
  summary.total_ms = summary.compile_ms + MillisecondsSince(start_total);
  if (substep_ms > 0.0) {
    summary.particle_steps_per_s =
        double(summary.particles) * summary.substeps / (substep_ms * 1e-3);
  }
  summary.peak_memory_mb = PeakResidentMegabytes();
  return summary;
}

}  // namespace culinarycut::cc_cut
