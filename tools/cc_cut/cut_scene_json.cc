// CutScene <-> JSON. Every error names the field at fault: "knife.descent_speed_m_s: must be > 0".
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "tools/cc_cut/cut_scene.h"
#include "sim/mpm/food_shapes.h"

namespace culinarycut::mpm {
namespace {

using nlohmann::json;

[[noreturn]] void Fail(const std::string& field, const std::string& problem) {
  throw std::invalid_argument(field + ": " + problem);
}

std::string Show(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string TypeName(const json& value) {
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_boolean()) return "a boolean";
  if (value.is_array()) return "an array";
  if (value.is_object()) return "an object";
  return "null";
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

// Reads the members of one JSON object, each by name; Finish() rejects the keys nobody read.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path) : object_(object), path_(std::move(path)) {
    if (!object_.is_object()) Fail(Display(), "expected an object, got " + TypeName(object_));
  }

  bool Has(const std::string& key) const { return object_.contains(key); }
  std::string Field(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  const json* Get(const std::string& key) {
    read_.insert(key);
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  // A finite number, checked by `in_range` (described by `range`, e.g. "> 0").
  template <typename InRange>
  bool Number(const std::string& key, double* out, InRange in_range, const std::string& range) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_number()) Fail(Field(key), "expected a number, got " + TypeName(*value));
    const double number = value->get<double>();
    if (!std::isfinite(number) || !in_range(number)) {
      Fail(Field(key), "must be " + range + ", got " + Show(number));
    }
    *out = number;
    return true;
  }
  template <typename InRange>
  void Optional(const std::string& key, std::optional<double>* out, InRange in_range,
                const std::string& range) {
    double number = 0.0;
    if (Number(key, &number, in_range, range)) *out = number;
  }

  void Integer(const std::string& key, int* out, int min_value) {
    const json* value = Get(key);
    if (value == nullptr) return;
    if (!value->is_number_integer())
      Fail(Field(key), "expected an integer, got " + TypeName(*value));
    const auto number = value->get<std::int64_t>();
    if (number < min_value || number > 1000000) {
      Fail(Field(key),
           "must be >= " + std::to_string(min_value) + ", got " + std::to_string(number));
    }
    *out = static_cast<int>(number);
  }

  void Unsigned(const std::string& key, std::uint64_t* out) {
    const json* value = Get(key);
    if (value == nullptr) return;
    if (!value->is_number_integer())
      Fail(Field(key), "expected an integer, got " + TypeName(*value));
    if (!value->is_number_unsigned()) Fail(Field(key), "must be >= 0");
    *out = value->get<std::uint64_t>();
  }

  void Bool(const std::string& key, bool* out) {
    const json* value = Get(key);
    if (value == nullptr) return;
    if (!value->is_boolean()) Fail(Field(key), "expected true or false, got " + TypeName(*value));
    *out = value->get<bool>();
  }

  void String(const std::string& key, std::string* out) {
    const json* value = Get(key);
    if (value == nullptr) return;
    if (!value->is_string()) Fail(Field(key), "expected a string, got " + TypeName(*value));
    *out = value->get<std::string>();
  }

  // An array of `min_size` to `max_size` finite numbers.
  std::vector<double> Numbers(const std::string& key, std::size_t min_size, std::size_t max_size) {
    const json* value = Get(key);
    if (value == nullptr) return {};
    const std::string sizes = min_size == max_size
                                  ? std::to_string(min_size)
                                  : std::to_string(min_size) + " or " + std::to_string(max_size);
    if (!value->is_array() || value->size() < min_size || value->size() > max_size) {
      Fail(Field(key), "expected an array of " + sizes + " numbers, got " + TypeName(*value));
    }
    std::vector<double> numbers;
    for (const json& element : *value) {
      if (!element.is_number() || !std::isfinite(element.get<double>())) {
        Fail(Field(key), "expected an array of " + sizes + " finite numbers");
      }
      numbers.push_back(element.get<double>());
    }
    return numbers;
  }

  // A nested object, or nullptr when absent.
  const json* Object(const std::string& key) {
    const json* value = Get(key);
    if (value != nullptr && !value->is_object()) {
      Fail(Field(key), "expected an object, got " + TypeName(*value));
    }
    return value;
  }

  void Finish() const {
    for (const auto& item : object_.items()) {
      if (read_.count(item.key()) == 0) Fail(Field(item.key()), "unknown key");
    }
  }

 private:
  std::string Display() const { return path_.empty() ? "scene" : path_; }

  const json& object_;
  std::string path_;
  std::set<std::string> read_;
};

const auto kPositive = [](double v) { return v > 0.0; };
const auto kNonNegative = [](double v) { return v >= 0.0; };
const auto kAny = [](double) { return true; };

void ReadFood(const json& object, CutSceneFood* food) {
  ObjectReader reader(object, "food");
  reader.String("name", &food->name);
  const std::vector<std::string> foods = FoodShapeNames();
  if (std::find(foods.begin(), foods.end(), food->name) == foods.end()) {
    Fail("food.name", "unknown food '" + food->name + "' (one of: " + JoinNames(foods) + ")");
  }
  reader.Number(
      "scale", &food->scale, [](double v) { return v > 0.0 && v <= 10.0; }, "in (0, 10]");
  const std::vector<double> position = reader.Numbers("position_m", 2, 3);
  if (!position.empty()) {
    food->position_xy_m = Eigen::Vector2d(position[0], position[1]);
    food->position_z_m.reset();
    if (position.size() == 3) food->position_z_m = position[2];
  }
  reader.Number("yaw_deg", &food->yaw_deg, kAny, "finite");
  reader.Finish();
}

void ReadMaterial(const json& object, CutSceneMaterial* material) {
  ObjectReader reader(object, "material");
  reader.String("preset", &material->preset);
  const std::vector<std::string> presets = MaterialPresetNames();
  if (!material->preset.empty() &&
      std::find(presets.begin(), presets.end(), material->preset) == presets.end()) {
    Fail("material.preset",
         "unknown preset '" + material->preset + "' (one of: " + JoinNames(presets) + ")");
  }
  reader.Optional("youngs_modulus_pa", &material->youngs_modulus_pa, kPositive, "> 0");
  reader.Optional(
      "poisson_ratio", &material->poisson_ratio, [](double v) { return v > -1.0 && v < 0.5; },
      "in (-1, 0.5)");
  reader.Optional("density_kg_m3", &material->density_kg_m3, kPositive, "> 0");
  reader.Optional("yield_stress_pa", &material->yield_stress_pa, kNonNegative, ">= 0");
  reader.Optional("friction_coefficient", &material->friction_coefficient, kNonNegative, ">= 0");
  reader.Optional("viscoplastic_relaxation_time_s", &material->viscoplastic_relaxation_time_s,
                  kNonNegative, ">= 0");
  reader.Finish();
}

void ReadEffects(const json& object, Effects* effects) {
  ObjectReader reader(object, "solver.effects");
  reader.Bool("plasticity", &effects->plasticity);
  reader.Bool("damage", &effects->damage);
  reader.Bool("friction", &effects->friction);
  reader.Bool("two_sided_blade", &effects->two_sided_blade);
  reader.Bool("force_sensing", &effects->force_sensing);
  reader.Finish();
}

void ReadCutting(const json& object, CuttingParameters* cutting) {
  ObjectReader reader(object, "solver.cutting");
  reader.Number("band0_m", &cutting->band0_m, kPositive, "> 0");
  reader.Number("band_reference_dx_m", &cutting->band_reference_dx_m, kPositive, "> 0");
  reader.Number("band_gamma", &cutting->band_gamma, kAny, "finite");
  reader.Number("v_hat", &cutting->v_hat, kNonNegative, ">= 0");
  reader.Number("c_hat_min", &cutting->c_hat_min, kNonNegative, ">= 0");
  reader.Number("damage_per_band", &cutting->damage_per_band, kNonNegative, ">= 0");
  reader.Number("k2_reference_per_s", &cutting->k2_reference_per_s, kNonNegative, ">= 0");
  reader.Number("k2_reference_youngs_pa", &cutting->k2_reference_youngs_pa, kPositive, "> 0");
  reader.Number("k2_reference_yield_pa", &cutting->k2_reference_yield_pa, kPositive, "> 0");
  reader.Number("tip_acceleration_m_s2", &cutting->tip_acceleration_m_s2, kNonNegative, ">= 0");
  reader.Number("tip_band_cells", &cutting->tip_band_cells, kNonNegative, ">= 0");
  reader.Finish();
}

void ReadSolver(const json& object, SolverConfig* config, int* particles_per_cell) {
  ObjectReader reader(object, "solver");
  reader.Number(
      "dx_m", &config->dx_m, [](double v) { return v > 0.0 && v <= 0.1; }, "in (0, 0.1]");
  reader.Integer("particles_per_cell", particles_per_cell, 1);
  reader.Number(
      "cfl", &config->cfl, [](double v) { return v > 0.0 && v <= 1.0; }, "in (0, 1]");
  reader.Number("max_dt_s", &config->max_dt_s, kPositive, "> 0");
  reader.Number(
      "j_min", &config->j_min, [](double v) { return v > 0.0 && v < 1.0; }, "in (0, 1)");
  reader.Number(
      "j_max", &config->j_max, [](double v) { return v > 1.0; }, "> 1");
  reader.Number("max_particle_speed_m_s", &config->max_particle_speed_m_s, kPositive, "> 0");
  reader.Number("max_grid_speed_m_s", &config->max_grid_speed_m_s, kPositive, "> 0");
  reader.Number("grid_damping_per_s", &config->grid_damping_per_s, kNonNegative, ">= 0");
  const std::vector<double> gravity = reader.Numbers("gravity_m_s2", 3, 3);
  if (!gravity.empty()) config->gravity_m_s2 = Eigen::Vector3d(gravity[0], gravity[1], gravity[2]);
  reader.Integer("grid_margin_cells", &config->grid_margin_cells, 1);
  reader.Integer("threads", &config->threads, 1);
  if (const json* effects = reader.Object("effects")) ReadEffects(*effects, &config->effects);
  if (const json* cutting = reader.Object("cutting")) ReadCutting(*cutting, &config->cutting);
  reader.Finish();
}

void ReadKnife(const json& object, CutSceneKnife* knife) {
  ObjectReader reader(object, "knife");
  if (reader.Has("cut_fraction") && reader.Has("cut_local_x_m")) {
    Fail("knife.cut_fraction", "give either cut_fraction or cut_local_x_m, not both");
  }
  reader.Optional(
      "cut_fraction", &knife->cut_fraction, [](double v) { return v > 0.0 && v < 1.0; },
      "in (0, 1)");
  reader.Optional("cut_local_x_m", &knife->cut_local_x_m, kAny, "finite");
  if (knife->cut_fraction && knife->cut_local_x_m) knife->cut_fraction.reset();
  reader.Number("start_above_top_m", &knife->start_above_top_m, kNonNegative, ">= 0");
  reader.Number("end_below_bottom_m", &knife->end_below_bottom_m, kNonNegative, ">= 0");
  reader.Number(
      "descent_speed_m_s", &knife->descent_speed_m_s, [](double v) { return v > 0.0 && v <= 20.0; },
      "in (0, 20]");
  reader.Number("saw_amplitude_m", &knife->saw_amplitude_m, kNonNegative, ">= 0");
  reader.Number("saw_frequency_hz", &knife->saw_frequency_hz, kNonNegative, ">= 0");
  reader.Number(
      "lift_speed_m_s", &knife->lift_speed_m_s, [](double v) { return v > 0.0 && v <= 20.0; },
      "in (0, 20]");
  reader.Number("settle_s", &knife->settle_s, kNonNegative, ">= 0");
  reader.Bool("apply_speed_resistance", &knife->apply_speed_resistance);
  reader.Number(
      "min_speed_fraction", &knife->min_speed_fraction,
      [](double v) { return v > 0.0 && v <= 1.0; }, "in (0, 1]");
  reader.Number("max_time_s", &knife->max_time_s, kPositive, "> 0");
  reader.Finish();
}

// Checks that need the food's size.
void CheckAgainstFood(const CutScene& scene) {
  const auto shape = MakeFoodShape(scene.food.name, scene.food.scale);
  const Eigen::AlignedBox3d bounds = shape->LocalBounds();
  if (scene.knife.cut_local_x_m && (*scene.knife.cut_local_x_m <= bounds.min().x() ||
                                    *scene.knife.cut_local_x_m >= bounds.max().x())) {
    Fail("knife.cut_local_x_m", "must lie within the food, in (" + Show(bounds.min().x()) + ", " +
                                    Show(bounds.max().x()) + ") m, got " +
                                    Show(*scene.knife.cut_local_x_m));
  }
}

}  // namespace

Material ResolveMaterial(const CutScene& scene) {
  const std::string preset =
      scene.material.preset.empty() ? scene.food.name : scene.material.preset;
  Material material;
  try {
    material = MaterialPreset(preset);
  } catch (const std::invalid_argument& error) {
    Fail("material.preset", error.what());
  }
  const CutSceneMaterial& m = scene.material;
  if (m.youngs_modulus_pa) material.youngs_modulus_pa = *m.youngs_modulus_pa;
  if (m.poisson_ratio) material.poisson_ratio = *m.poisson_ratio;
  if (m.density_kg_m3) material.density_kg_m3 = *m.density_kg_m3;
  if (m.yield_stress_pa) material.yield_stress_pa = *m.yield_stress_pa;
  if (m.friction_coefficient) material.friction_coefficient = *m.friction_coefficient;
  if (m.viscoplastic_relaxation_time_s) {
    material.viscoplastic_relaxation_time_s = *m.viscoplastic_relaxation_time_s;
  }
  try {
    ValidateMaterial(material);
  } catch (const std::invalid_argument& error) {
    Fail("material", error.what());
  }
  return material;
}

CutScene CutSceneFromJson(const std::string& json_text) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& error) {
    throw std::invalid_argument(std::string("invalid JSON: ") + error.what());
  }
  CutScene scene;
  ObjectReader reader(root, "");
  reader.String("description", &scene.description);
  if (const json* food = reader.Object("food")) ReadFood(*food, &scene.food);
  if (const json* material = reader.Object("material")) ReadMaterial(*material, &scene.material);
  if (const json* solver = reader.Object("solver")) {
    ReadSolver(*solver, &scene.solver, &scene.particles_per_cell);
  }
  if (const json* knife = reader.Object("knife")) ReadKnife(*knife, &scene.knife);
  reader.Unsigned("seed", &scene.seed);
  reader.Finish();
  try {
    ValidateSolverConfig(scene.solver);
  } catch (const std::invalid_argument& error) {
    Fail("solver", error.what());
  }
  ResolveMaterial(scene);
  CheckAgainstFood(scene);
  return scene;
}

std::string CutSceneToJson(const CutScene& scene) {
  json food = {{"name", scene.food.name},
               {"scale", scene.food.scale},
               {"position_m", {scene.food.position_xy_m.x(), scene.food.position_xy_m.y()}},
               {"yaw_deg", scene.food.yaw_deg}};
  if (scene.food.position_z_m) food["position_m"].push_back(*scene.food.position_z_m);

  json material = json::object();
  material["preset"] = scene.material.preset;
  const CutSceneMaterial& m = scene.material;
  if (m.youngs_modulus_pa) material["youngs_modulus_pa"] = *m.youngs_modulus_pa;
  if (m.poisson_ratio) material["poisson_ratio"] = *m.poisson_ratio;
  if (m.density_kg_m3) material["density_kg_m3"] = *m.density_kg_m3;
  if (m.yield_stress_pa) material["yield_stress_pa"] = *m.yield_stress_pa;
  if (m.friction_coefficient) material["friction_coefficient"] = *m.friction_coefficient;
  if (m.viscoplastic_relaxation_time_s) {
    material["viscoplastic_relaxation_time_s"] = *m.viscoplastic_relaxation_time_s;
  }

  const SolverConfig& s = scene.solver;
  const CuttingParameters& c = s.cutting;
  const json solver = {
      {"dx_m", s.dx_m},
      {"particles_per_cell", scene.particles_per_cell},
      {"cfl", s.cfl},
      {"max_dt_s", s.max_dt_s},
      {"j_min", s.j_min},
      {"j_max", s.j_max},
      {"max_particle_speed_m_s", s.max_particle_speed_m_s},
      {"max_grid_speed_m_s", s.max_grid_speed_m_s},
      {"grid_damping_per_s", s.grid_damping_per_s},
      {"gravity_m_s2", {s.gravity_m_s2.x(), s.gravity_m_s2.y(), s.gravity_m_s2.z()}},
      {"grid_margin_cells", s.grid_margin_cells},
      {"threads", s.threads},
      {"effects",
       {{"plasticity", s.effects.plasticity},
        {"damage", s.effects.damage},
        {"friction", s.effects.friction},
        {"two_sided_blade", s.effects.two_sided_blade},
        {"force_sensing", s.effects.force_sensing}}},
      {"cutting",
       {{"band0_m", c.band0_m},
        {"band_reference_dx_m", c.band_reference_dx_m},
        {"band_gamma", c.band_gamma},
        {"v_hat", c.v_hat},
        {"c_hat_min", c.c_hat_min},
        {"damage_per_band", c.damage_per_band},
        {"k2_reference_per_s", c.k2_reference_per_s},
        {"k2_reference_youngs_pa", c.k2_reference_youngs_pa},
        {"k2_reference_yield_pa", c.k2_reference_yield_pa},
        {"tip_acceleration_m_s2", c.tip_acceleration_m_s2},
        {"tip_band_cells", c.tip_band_cells}}}};

  const CutSceneKnife& k = scene.knife;
  json knife = {{"start_above_top_m", k.start_above_top_m},
                {"end_below_bottom_m", k.end_below_bottom_m},
                {"descent_speed_m_s", k.descent_speed_m_s},
                {"saw_amplitude_m", k.saw_amplitude_m},
                {"saw_frequency_hz", k.saw_frequency_hz},
                {"lift_speed_m_s", k.lift_speed_m_s},
                {"settle_s", k.settle_s},
                {"apply_speed_resistance", k.apply_speed_resistance},
                {"min_speed_fraction", k.min_speed_fraction},
                {"max_time_s", k.max_time_s}};
  if (k.cut_local_x_m) {
    knife["cut_local_x_m"] = *k.cut_local_x_m;
  } else {
    knife["cut_fraction"] = k.cut_fraction.value_or(0.5);
  }

  const json root = {{"description", scene.description},
                     {"food", food},
                     {"material", material},
                     {"solver", solver},
                     {"knife", knife},
                     {"seed", scene.seed}};
  return root.dump(2);
}

}  // namespace culinarycut::mpm
