// CutScene <-> JSON. Every error names the field at fault: "knife.descent_speed_m_s: must be > 0".
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "tools/cc_cut/cut_scene.h"
#include "tools/cc_cut/json_object_reader.h"
#include "tools/cc_cut/scene_spec_json.h"

namespace culinarycut::cc_cut {
namespace {

using nlohmann::json;

NumberRange GreaterThanOne() { return {[](double v) { return v > 1.0; }, "> 1"}; }

// Where the keys of the schema before SceneSpec went, for the messages on old files.
const std::vector<std::pair<std::string, std::string>> kMovedTopLevelKeys = {
    {"food", "the food is scene.objects[0]: food, scale, pose"},
    {"material", "use scene.objects[0].material and material_overrides"},
    {"seed", "use scene.seed"}};
const std::vector<std::pair<std::string, std::string>> kMovedSolverKeys = {
    {"dx_m", "use scene.mpm.dx"},
    {"particles_per_cell", "use scene.mpm.particles_per_cell"},
    {"cfl", "use scene.mpm.cfl"},
    {"effects", "use scene.effects; two_sided_blade is solver.two_sided_blade"}};
const std::vector<std::pair<std::string, std::string>> kMovedKnifeKeys = {
    {"cut_local_x_m", "use cut_from_centre_m, along the long axis towards its right end"}};

void ReadCutting(const json& object, CuttingOverrides* cutting) {
  JsonObjectReader reader(object, "solver.cutting");
  reader.Number("band0_m", &cutting->band0_m, Positive());
  reader.Number("band_reference_dx_m", &cutting->band_reference_dx_m, Positive());
  reader.Number("band_gamma", &cutting->band_gamma, AnyFinite());
  reader.Number("v_hat", &cutting->v_hat, NonNegative());
  reader.Number("c_hat_min", &cutting->c_hat_min, NonNegative());
  reader.Number("damage_per_band", &cutting->damage_per_band, NonNegative());
  reader.Number("k2_reference_per_s", &cutting->k2_reference_per_s, NonNegative());
  reader.Number("k2_reference_youngs_pa", &cutting->k2_reference_youngs_pa, Positive());
  reader.Number("k2_reference_yield_pa", &cutting->k2_reference_yield_pa, Positive());
  reader.Number("tip_acceleration_m_s2", &cutting->tip_acceleration_m_s2, NonNegative());
  reader.Number("tip_band_cells", &cutting->tip_band_cells, NonNegative());
  reader.Finish();
}

void ReadSolver(const json& object, SolverOverrides* solver) {
  JsonObjectReader reader(object, "solver");
  reader.Integer("threads", &solver->threads, 1, 1024);
  reader.Number("max_dt_s", &solver->max_dt_s, Positive());
  reader.Number("j_min", &solver->j_min, OpenInterval(0.0, 1.0));
  reader.Number("j_max", &solver->j_max, GreaterThanOne());
  reader.Number("max_particle_speed_m_s", &solver->max_particle_speed_m_s, Positive());
  reader.Number("max_grid_speed_m_s", &solver->max_grid_speed_m_s, Positive());
  reader.Number("grid_damping_per_s", &solver->grid_damping_per_s, NonNegative());
  const std::vector<double> gravity = reader.Numbers("gravity_m_s2", 3);
  if (!gravity.empty()) solver->gravity_m_s2 = Eigen::Vector3d(gravity[0], gravity[1], gravity[2]);
  reader.Integer("grid_margin_cells", &solver->grid_margin_cells, 1, 1000);
  reader.Number("activity_sleep_speed_m_s", &solver->activity_sleep_speed_m_s, NonNegative());
  reader.Number("activity_wake_speed_m_s", &solver->activity_wake_speed_m_s, Positive());
  reader.Integer("activity_check_every_substeps", &solver->activity_check_every_substeps, 1, 100000);
  reader.Integer("activity_quiet_checks", &solver->activity_quiet_checks, 1, 254);
  reader.Bool("two_sided_blade", &solver->two_sided_blade);
  if (const json* cutting = reader.Object("cutting")) ReadCutting(*cutting, &solver->cutting);
  reader.Finish(kMovedSolverKeys);
}

void ReadKnife(const json& object, KnifePath* knife) {
  JsonObjectReader reader(object, "knife");
  if (reader.Has("cut_fraction") && reader.Has("cut_from_centre_m")) {
    FailField("knife.cut_fraction", "give either cut_fraction or cut_from_centre_m, not both");
  }
  reader.Number("cut_fraction", &knife->cut_fraction, OpenInterval(0.0, 1.0));
  reader.Number("cut_from_centre_m", &knife->cut_from_centre_m, AnyFinite());
  reader.Number("start_above_top_m", &knife->start_above_top_m, NonNegative());
  reader.Number("end_below_bottom_m", &knife->end_below_bottom_m, NonNegative());
  reader.Number("descent_speed_m_s", &knife->descent_speed_m_s, HalfOpenInterval(0.0, 20.0));
  reader.Number("saw_amplitude_m", &knife->saw_amplitude_m, NonNegative());
  reader.Number("saw_frequency_hz", &knife->saw_frequency_hz, NonNegative());
  reader.Number("lift_speed_m_s", &knife->lift_speed_m_s, HalfOpenInterval(0.0, 20.0));
  reader.Number("settle_s", &knife->settle_s, NonNegative());
  reader.Number("force_window_s", &knife->force_window_s, HalfOpenInterval(0.0, 1.0));
  reader.Bool("apply_speed_resistance", &knife->apply_speed_resistance);
  reader.Number("min_speed_fraction", &knife->min_speed_fraction, HalfOpenInterval(0.0, 1.0));
  reader.Number("max_time_s", &knife->max_time_s, Positive());
  reader.Finish(kMovedKnifeKeys);
}

template <typename T>
void Put(json* object, const char* key, const std::optional<T>& value) {
  if (value) (*object)[key] = *value;
}

json SolverJson(const SolverOverrides& s) {
  json solver = json::object();
  Put(&solver, "threads", s.threads);
  Put(&solver, "max_dt_s", s.max_dt_s);
  Put(&solver, "j_min", s.j_min);
  Put(&solver, "j_max", s.j_max);
  Put(&solver, "max_particle_speed_m_s", s.max_particle_speed_m_s);
  Put(&solver, "max_grid_speed_m_s", s.max_grid_speed_m_s);
  Put(&solver, "grid_damping_per_s", s.grid_damping_per_s);
  if (s.gravity_m_s2) solver["gravity_m_s2"] = {s.gravity_m_s2->x(), s.gravity_m_s2->y(), s.gravity_m_s2->z()};
  Put(&solver, "grid_margin_cells", s.grid_margin_cells);
  Put(&solver, "activity_sleep_speed_m_s", s.activity_sleep_speed_m_s);
  Put(&solver, "activity_wake_speed_m_s", s.activity_wake_speed_m_s);
  Put(&solver, "activity_check_every_substeps", s.activity_check_every_substeps);
  Put(&solver, "activity_quiet_checks", s.activity_quiet_checks);
  Put(&solver, "two_sided_blade", s.two_sided_blade);
  const CuttingOverrides& c = s.cutting;
  json cutting = json::object();
  Put(&cutting, "band0_m", c.band0_m);
  Put(&cutting, "band_reference_dx_m", c.band_reference_dx_m);
  Put(&cutting, "band_gamma", c.band_gamma);
  Put(&cutting, "v_hat", c.v_hat);
  Put(&cutting, "c_hat_min", c.c_hat_min);
  Put(&cutting, "damage_per_band", c.damage_per_band);
  Put(&cutting, "k2_reference_per_s", c.k2_reference_per_s);
  Put(&cutting, "k2_reference_youngs_pa", c.k2_reference_youngs_pa);
  Put(&cutting, "k2_reference_yield_pa", c.k2_reference_yield_pa);
  Put(&cutting, "tip_acceleration_m_s2", c.tip_acceleration_m_s2);
  Put(&cutting, "tip_band_cells", c.tip_band_cells);
  if (!cutting.empty()) solver["cutting"] = cutting;
  return solver;
}

json KnifeJson(const KnifePath& k) {
  json knife = {{"start_above_top_m", k.start_above_top_m},
                {"end_below_bottom_m", k.end_below_bottom_m},
                {"descent_speed_m_s", k.descent_speed_m_s},
                {"saw_amplitude_m", k.saw_amplitude_m},
                {"saw_frequency_hz", k.saw_frequency_hz},
                {"lift_speed_m_s", k.lift_speed_m_s},
                {"settle_s", k.settle_s},
                {"force_window_s", k.force_window_s},
                {"apply_speed_resistance", k.apply_speed_resistance},
                {"min_speed_fraction", k.min_speed_fraction},
                {"max_time_s", k.max_time_s}};
  if (k.cut_from_centre_m) {
    knife["cut_from_centre_m"] = *k.cut_from_centre_m;
  } else {
    knife["cut_fraction"] = k.cut_fraction.value_or(0.5);
  }
  return knife;
}

// {"shape": "box" | "half_cylinder", "size_m": [length, width, height]}: shapes are checked at compile.
SpecimenConfig ReadSpecimen(const json& object) {
  JsonObjectReader reader(object, "specimen");
  SpecimenConfig specimen;
  if (!reader.String("shape", &specimen.kind)) FailField("specimen.shape", "is missing: box or half_cylinder");
  const std::vector<double> size = reader.Numbers("size_m", 3);
  if (size.empty()) FailField("specimen.size_m", "is missing: [length, width, height] in m");
  specimen.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
  reader.Finish();
  return specimen;
}

}  // namespace

CutScene CutSceneFromJson(const std::string& json_text) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& error) {
    throw std::invalid_argument(std::string("invalid JSON: ") + error.what());
  }
  CutScene scene;
  JsonObjectReader reader(root, "");
  reader.String("description", &scene.description);
  if (const json* spec = reader.Object("scene")) scene.scene = SceneSpecFromJson(*spec, "scene");
  if (const json* solver = reader.Object("solver")) ReadSolver(*solver, &scene.solver);
  if (const json* knife = reader.Object("knife")) ReadKnife(*knife, &scene.knife);
  if (const json* specimen = reader.Object("specimen")) scene.specimen = ReadSpecimen(*specimen);
  reader.Finish(kMovedTopLevelKeys);
  return scene;
}

std::string CutSceneToJson(const CutScene& scene) {
  json root = {{"description", scene.description},
               {"scene", SceneSpecToJson(scene.scene)},
               {"solver", SolverJson(scene.solver)},
               {"knife", KnifeJson(scene.knife)}};
  if (scene.specimen) {
    const Eigen::Vector3d& size = scene.specimen->size_m;
    root["specimen"] = {{"shape", scene.specimen->kind}, {"size_m", {size.x(), size.y(), size.z()}}};
  }
  return root.dump(2);
}

}  // namespace culinarycut::cc_cut
