#include "tools/cc_cut/outputs.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "sim/mpm/kernel_instruction_set.h"
#include "tools/cc_cut/scene_spec_json.h"

namespace culinarycut::cc_cut {
namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

void Number(double value, std::ostream& out) {
  char text[32];
  std::snprintf(text, sizeof(text), ",%.9g", value);
  out << text;
}

void Vector(const Eigen::Vector3d& v, std::ostream& out) {
  for (int axis = 0; axis < 3; ++axis) Number(v[axis], out);
}

json MaterialJson(const mpm::Material& m) {
  return {{"name", m.name},
          {"youngs_modulus_pa", m.youngs_modulus_pa},
          {"poisson_ratio", m.poisson_ratio},
          {"density_kg_m3", m.density_kg_m3},
          {"yield_stress_pa", m.yield_stress_pa},
          {"viscoplastic_relaxation_time_s", m.viscoplastic_relaxation_time_s},
          {"friction_coefficient", m.friction_coefficient},
          {"board_friction_coefficient", m.board_friction_coefficient},
          {"fracture_toughness_j_m2", m.fracture_toughness_j_m2},
          {"maxwell_modulus_ratio", m.maxwell_modulus_ratio},
          {"maxwell_relaxation_time_s", m.maxwell_relaxation_time_s},
          {"dilatational_wave_speed_m_s", m.dilatational_wave_speed_m_s()},
          {"source", m.source}};
}

json ResolvedJson(const CutModel& model, const CutSummary& s) {
  const mpm::SolverConfig& config = model.food.solver->config;
  const mpm::CuttingParameters& cutting = config.cutting;
  const SceneLayout& layout = model.layout;
  const double dx = config.dx_m;
  const double band_m =
      cutting.band0_m * std::pow(cutting.band_reference_dx_m / dx, cutting.band_gamma);
  const mpm::TopologyOptions& topology = model.food.topology;
  return {{"scene", SceneSpecToJson(ResolvedSceneSpec(model))},
          {"material", MaterialJson(s.material)},
          {"dx_m", dx},
          {"dt_s", s.dt_s},
          {"particles_per_cell", model.food.resolution.particles_per_cell},
          {"mass_scaling", config.mass_scaling},
          {"activity_radius_m", config.activity.radius_m},
          {"particles", s.particles},
          {"threads", config.threads},
          {"effects",
           {{"plasticity", config.effects.plasticity},
            {"damage", config.effects.damage},
            {"friction", config.effects.friction},
            {"two_sided_blade", config.effects.two_sided_blade},
            {"force_sensing", config.effects.force_sensing}}},
          {"grid_damping_per_s", config.grid_damping_per_s},
          {"gravity_m_s2", Vec(config.gravity_m_s2)},
          {"thresholds",
           {{"j_min", config.j_min},
            {"j_max", config.j_max},
            {"damage_band_half_width_m", band_m},
            {"approach_speed_threshold_m_s", dx / s.dt_s * cutting.v_hat},
            {"c_hat_min", cutting.c_hat_min},
            {"max_particle_speed_m_s", config.max_particle_speed_m_s},
            {"max_grid_speed_m_s", config.max_grid_speed_m_s}}},
          {"food",
           {{"length_m", s.food_length_m},
            {"axis_origin_m", Vec(s.axis_origin_m)},
            {"axis_direction", Vec(s.axis_direction)}}},
          {"knife",
           {{"cut_position_m", s.requested_cut_m},
            {"cut_fraction", s.requested_cut_m / s.food_length_m},
            {"start_height_m", s.start_height_m},
            {"end_height_m", s.end_height_m}}},
          {"board", {{"size_m", Vec(layout.board_size_m)}, {"centre_m", Vec(layout.board_center_m)}}},
          {"table_height_m", layout.table_center_m.z() + 0.5 * layout.table_size_m.z()},
          {"topology",
           {{"link_distance_m", topology.link_distance_m},
            {"broken_damage", topology.broken_damage},
            {"min_piece_particles", topology.min_piece_particles},
            {"separate_blade_sides", topology.separate_blade_sides}}}};
}

json ResultJson(const CutSummary& s) {
  json pieces = json::array();
  for (const mpm::Piece& piece : s.pieces) {
    pieces.push_back({{"label", piece.label},
                      {"particles", piece.particle_count},
                      {"volume_m3", piece.volume_m3},
                      {"mass_kg", piece.mass_kg},
                      {"centroid_m", Vec(piece.centroid_m)},
                      {"bounds_min_m", Vec(piece.bounds_m.min())},
                      {"bounds_max_m", Vec(piece.bounds_m.max())},
                      {"rest_bounds_min_m", Vec(piece.rest_bounds_m.min())},
                      {"rest_bounds_max_m", Vec(piece.rest_bounds_m.max())}});
  }
  json cut_fractions = json::array();
  for (const double cut_m : s.cut_positions_m) cut_fractions.push_back(cut_m / s.food_length_m);
  return {{"substeps", s.substeps},
          {"min_dt_s", s.min_dt_s},
          {"sim_time_s", s.sim_time_s},
          {"hit_time_limit", s.hit_time_limit},
          {"pieces", pieces},
          {"cut_positions_m", s.cut_positions_m},
          {"cut_fractions", cut_fractions},
          {"peak_blade_force_n", s.peak_blade_force_n},
          {"peak_blade_force_time_s", s.peak_blade_force_time_s},
          {"peak_substep_blade_force_n", s.peak_substep_blade_force_n},
          {"momentum",
           {{"blade_impulse_n_s", Vec(s.blade_impulse_n_s)},
            {"external_impulse_n_s", Vec(s.external_impulse_n_s)},
            {"momentum_change_n_s", Vec(s.momentum_change_n_s)},
            {"mismatch", s.momentum_mismatch},
            {"worst_substep_residual", s.worst_momentum_residual}}},
          {"j_min", s.j_min},
          {"j_max", s.j_max},
          {"j_clamps", s.j_clamps},
          {"speed_caps", s.speed_caps},
          {"broken_particles", s.broken_particles},
          {"min_speed_factor", s.min_speed_factor},
          {"kinetic_to_elastic_energy", s.kinetic_to_elastic_energy},
          {"active_particle_fraction", s.active_particle_fraction},
          {"wall_time_ms",
           {{"compile", s.compile_ms},
            {"setup", s.setup_ms},
            {"p2g", s.p2g_ms},
            {"grid", s.grid_ms},
            {"g2p", s.g2p_ms},
            {"topology", s.topology_ms},
            {"total", s.total_ms}}},
          {"particle_steps_per_s", s.particle_steps_per_s},
          {"peak_memory_mb", s.peak_memory_mb}};
}

}  // namespace

void WriteStepsHeader(std::ostream& out) {
  out << "step,t_s,dt_s,knife_z_m,knife_vx_m_s,knife_vy_m_s,knife_vz_m_s,"
         "blade_fx_n,blade_fy_n,blade_fz_n,edge_fx_n,edge_fy_n,edge_fz_n,handle_fx_n,handle_fy_n,handle_fz_n,"
         "board_fx_n,board_fy_n,board_fz_n,table_fx_n,table_fy_n,table_fz_n,"
         "c_hat,speed_factor,j_min,j_max,j_clamps,speed_caps,damaged,"
         "kinetic_energy_j,elastic_energy_j,momentum_residual,fastest_particle_m_s\n";
}

void WriteFinalParticles(const FinalParticles& particles, std::ostream& out) {
  out << "rest_x_m,rest_y_m,rest_z_m,x_m,y_m,z_m,piece\n";
  const auto& rest = particles.rest_position_m;
  const auto& now = particles.position_m;
  char row[160];
  for (std::size_t q = 0; q < particles.piece.size(); ++q) {
    std::snprintf(row, sizeof(row), "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", rest[0][q], rest[1][q], rest[2][q],
                  now[0][q], now[1][q], now[2][q], particles.piece[q]);
    out << row;
  }
}

void WriteStepRow(const CutStepRecord& record, std::ostream& out) {
  const mpm::SubstepDiagnostics& d = record.diagnostics;
  out << record.step;
  Number(record.time_s, out);
  Number(d.dt_s, out);
  Number(record.knife_height_m, out);
  Vector(d.knife_velocity_m_s, out);
  Vector(d.force_on_blade_n, out);
  Vector(d.force_on_edge_n, out);
  Vector(d.force_on_handle_n, out);
  Vector(d.force_on_board_n, out);
  Vector(d.force_on_table_n, out);
  Number(d.c_hat, out);
  Number(d.knife_speed_factor, out);
  Number(d.j_min, out);
  Number(d.j_max, out);
  out << ',' << d.j_clamps << ',' << d.speed_caps << ',' << d.damaged_particles;
  Number(d.kinetic_energy_j, out);
  Number(d.elastic_energy_j, out);
  Number(d.momentum_residual, out);
  Number(d.fastest_particle_m_s, out);
  out << '\n';
}

std::string SummaryJson(const std::string& scene_path, const CutScene& scene, const CutModel& model,
                        const CutSummary& summary) {
  const json root = {{"tool", "cc-cut"},
                     {"simd", mpm::KernelInstructionSet()},  // results are the same bits only within one
                     {"scene_file", scene_path},
                     {"scene", json::parse(CutSceneToJson(scene))},
                     {"resolved", ResolvedJson(model, summary)},
                     {"summary", ResultJson(summary)}};
  return root.dump(2) + "\n";
}

void PrintSummary(const CutModel& model, const CutSummary& s, std::ostream& out) {
  const FoodConfig& food = model.config.foods.front();
  char line[256];
  std::snprintf(line, sizeof(line),
                "%s (scale %.2f, %s E %.3g Pa): %zu particles, dx %.1f mm, dt %.3g s\n",
                food.food.c_str(), food.scale, s.material.name.c_str(), s.material.youngs_modulus_pa,
                s.particles, model.food.resolution.dx_m * 1e3, s.dt_s);
  out << line;
  std::snprintf(line, sizeof(line), "pieces: %zu%s\n", s.pieces.size(),
                s.hit_time_limit ? "  (stopped at max_time_s)" : "");
  out << line;
  for (const mpm::Piece& piece : s.pieces) {
    std::snprintf(line, sizeof(line),
                  "  piece %d: %zu particles, %.2f cm^3, centroid (%.4f, %.4f, %.4f) m\n",
                  piece.label, piece.particle_count, piece.volume_m3 * 1e6, piece.centroid_m.x(),
                  piece.centroid_m.y(), piece.centroid_m.z());
    out << line;
  }
  std::snprintf(line, sizeof(line), "requested cut: %.1f mm from the left end (fraction %.3f)\n",
                s.requested_cut_m * 1e3, s.requested_cut_m / s.food_length_m);
  out << line;
  for (const double cut_m : s.cut_positions_m) {
    std::snprintf(line, sizeof(line), "  cut at %.1f mm (fraction %.3f)\n", cut_m * 1e3,
                  cut_m / s.food_length_m);
    out << line;
  }
  std::snprintf(line, sizeof(line), "peak blade force: %.3g N at t = %.4f s (over the accumulation window; "
                "single substep %.3g N)\n", s.peak_blade_force_n, s.peak_blade_force_time_s,
                s.peak_substep_blade_force_n);
  out << line;
  std::snprintf(line, sizeof(line),
                "J in [%.3f, %.3f], %lld clamps, %lld speed caps; momentum mismatch %.2e\n",
                s.j_min, s.j_max, static_cast<long long>(s.j_clamps),
                static_cast<long long>(s.speed_caps), s.momentum_mismatch);
  out << line;
  std::snprintf(line, sizeof(line),
                "runtime: %.2f s for %d substeps (%.3f s simulated); %.3g particle-steps/s\n"
                "  compile %.0f ms, setup %.0f ms, p2g %.0f ms, grid %.0f ms, g2p %.0f ms, topology %.0f ms\n",
                s.total_ms * 1e-3, s.substeps, s.sim_time_s, s.particle_steps_per_s, s.compile_ms,
                s.setup_ms, s.p2g_ms, s.grid_ms, s.g2p_ms, s.topology_ms);
  out << line;
}

}  // namespace culinarycut::cc_cut
