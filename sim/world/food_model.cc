#include "sim/world/food_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "sim/mpm/food_shapes.h"
#include "sim/mpm/specimen_shapes.h"
#include "sim/world/model.h"

namespace culinarycut {
namespace {

// The preset with the scene's overrides, validated.
mpm::Material ResolveFoodMaterial(const FoodConfig& food, const std::string& field) {
  mpm::Material material;
  try {
    material = mpm::MaterialPreset(food.material.empty() ? food.food : food.material);
  } catch (const std::invalid_argument& error) {
    throw SceneError(field + ".material: " + error.what());
  }
  for (const auto& [key, value] : food.material_overrides) {
    if (key == "youngs_modulus_pa") material.youngs_modulus_pa = value;
    else if (key == "poisson_ratio") material.poisson_ratio = value;
    else if (key == "density_kg_m3") material.density_kg_m3 = value;
    else if (key == "yield_stress_pa") material.yield_stress_pa = value;
    else if (key == "friction_coefficient") material.friction_coefficient = value;
    else if (key == "board_friction_coefficient") material.board_friction_coefficient = value;
    else if (key == "viscoplastic_relaxation_time_s") material.viscoplastic_relaxation_time_s = value;
    else if (key == "fracture_toughness_j_m2") material.fracture_toughness_j_m2 = value;
    else if (key == "maxwell_modulus_ratio") material.maxwell_modulus_ratio = value;
    else if (key == "maxwell_relaxation_time_s") material.maxwell_relaxation_time_s = value;
    else {
      throw SceneError(field + ".material_overrides: unknown key '" + key +
                       "'; use youngs_modulus_pa, poisson_ratio, density_kg_m3, yield_stress_pa, "
                       "friction_coefficient, board_friction_coefficient, viscoplastic_relaxation_time_s, "
                       "fracture_toughness_j_m2, maxwell_modulus_ratio or maxwell_relaxation_time_s");
    }
  }
  try {
    mpm::ValidateMaterial(material);
  } catch (const std::invalid_argument& error) {
    throw SceneError(field + ".material_overrides: " + error.what());
  }
  return material;
}

// Where a food lies: the given pose, or resting on the board at the given (x, y) or side by side
// along x, with the long axis left-right (world y) so "from the left" runs along the board's width.
Eigen::Isometry3d FoodPose(const FoodConfig& food, const mpm::FoodShape& shape, const SceneLayout& layout,
                           int index, int count) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = food.orientation ? food.orientation->normalized().toRotationMatrix()
                                   : Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (food.position_m) {
    pose.translation() = *food.position_m;
    return pose;
  }
  // Lowest point of the shape's box in its pose, so the food rests on the board.
  const Eigen::AlignedBox3d local = shape.LocalBounds();
  double lowest_m = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d world = pose.linear() * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
    lowest_m = std::min(lowest_m, world.z());
  }
  const double spacing_m = 0.12;  // between neighbouring objects along x
  const double board_top_m = layout.board_center_m.z() + 0.5 * layout.board_size_m.z();
  const Eigen::Vector2d xy_m = food.board_xy_m.value_or(Eigen::Vector2d(
      layout.board_center_m.x() + (index - 0.5 * (count - 1)) * spacing_m, layout.board_center_m.y()));
  pose.translation() = Eigen::Vector3d(xy_m.x(), xy_m.y(), board_top_m - lowest_m);
  return pose;
}

void CheckEffects(const SceneConfig& config) {
  const EffectsConfig& effects = config.effects;
  if (effects.mpm) {
    if (config.foods.empty()) throw SceneError("scene.effects.mpm is set but scene.objects is empty: add a food object");
    return;
  }
  if (!config.foods.empty()) {
    throw SceneError("scene.objects needs scene.effects.mpm = true: food objects are simulated with MPM");
  }
  const std::pair<bool, const char*> needs_mpm[] = {{effects.plasticity, "plasticity"}, {effects.damage, "damage"},
                                                    {effects.friction, "friction"}, {effects.topology, "topology"},
                                                    {effects.force_sensing, "force_sensing"}};
  for (const auto& [on, name] : needs_mpm) {
    if (on) throw SceneError(std::string("scene.effects.") + name + " needs scene.effects.mpm = true and a food object");
  }
}

// The food's box in the world (m): the corners of its local box in its pose.
Eigen::AlignedBox3d WorldBox(const mpm::FoodShape& shape, const Eigen::Isometry3d& pose) {
  const Eigen::AlignedBox3d local = shape.LocalBounds();
  Eigen::AlignedBox3d world;
  for (int corner = 0; corner < 8; ++corner) world.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  return world;
}

// Food lies on the table: over its top, from 1 cm below the surface to 1 m above it.
void CheckOnTable(const Eigen::AlignedBox3d& food_m, const SceneLayout& layout, const std::string& field) {
  const Eigen::Vector3d half = 0.5 * layout.table_size_m;
  const double top_m = layout.table_center_m.z() + half.z();
  const Eigen::AlignedBox3d allowed(
      Eigen::Vector3d(layout.table_center_m.x() - half.x(), layout.table_center_m.y() - half.y(), top_m - 0.01),
      Eigen::Vector3d(layout.table_center_m.x() + half.x(), layout.table_center_m.y() + half.y(), top_m + 1.0));
  if (!allowed.contains(food_m)) {
    throw SceneError(field + ".pose.position puts the food off the table: it must lie over the table top (x in [" +
                     std::to_string(allowed.min().x()) + ", " + std::to_string(allowed.max().x()) + "] m, y in [" +
                     std::to_string(allowed.min().y()) + ", " + std::to_string(allowed.max().y()) +
                     "] m, at most 1 m above it)");
  }
}

}  // namespace

FoodModel CompileFoodModel(const SceneConfig& config, const SceneLayout& layout) {
  CheckEffects(config);
  FoodModel food_model;
  std::vector<std::unique_ptr<mpm::FoodShape>> shapes;
  double smallest_food_m3 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < config.foods.size(); ++i) {
    const FoodConfig& food = config.foods[i];
    try {
      shapes.push_back(food.specimen ? mpm::MakeSpecimenShape(food.specimen->kind, food.specimen->size_m)
                                     : mpm::MakeFoodShape(food.food, food.scale));
    } catch (const std::invalid_argument& error) {
      throw SceneError("scene.objects[" + std::to_string(i) + "]: " + error.what());
    }
    // Specimens are verification geometry: their resolution is the test's to choose.
    if (!food.specimen) smallest_food_m3 = std::min(smallest_food_m3, mpm::EstimatedVolume(*shapes.back()));
  }
  food_model.resolution = ResolveMpmResolution(config.quality, config.accuracy_target, config.mpm);
  // A preset or target's dx is refined for a small food; an explicit scene.mpm.dx is kept as given.
  if (!config.mpm.dx_m && std::isfinite(smallest_food_m3)) {
    food_model.resolution.dx_m = DxForSmallestFood(food_model.resolution.dx_m, smallest_food_m3);
  }
  const MpmResolution& resolution = food_model.resolution;
  mpm::SolverModel solver_model;
  mpm::SolverConfig& solver = solver_model.config;
  solver.dx_m = resolution.dx_m;
  solver.cfl = resolution.cfl;
  solver.mass_scaling = resolution.mass_scaling;
  solver.activity.radius_m = resolution.activity_radius_m;
  solver.gravity_m_s2 = layout.gravity_m_s2;
  solver.effects.plasticity = config.effects.plasticity;
  solver.effects.damage = config.effects.damage;
  solver.effects.friction = config.effects.friction;
  solver.effects.force_sensing = config.effects.force_sensing;
  solver.effects.two_sided_blade = true;
  // A little grid damping lets the food come to rest on the board, so MPM can sleep again.
  solver.grid_damping_per_s = 2.0;
  food_model.activation_margin_m = kActivationMarginCells * resolution.dx_m;
  food_model.topology_update = config.effects.topology;
  food_model.topology.link_distance_m = 0.75 * resolution.dx_m;
  food_model.topology.min_piece_particles = 20;
  food_model.topology.separate_blade_sides = false;  // pieces part by the cut record and damage, not by transient labels
  food_model.particle_spacing_m = resolution.dx_m / std::cbrt(static_cast<double>(resolution.particles_per_cell));

  mpm::SamplingOptions sampling;
  sampling.dx_m = resolution.dx_m;
  sampling.particles_per_cell = resolution.particles_per_cell;
  sampling.seed = config.seed;
  const int count = static_cast<int>(config.foods.size());
  double estimated_particles = 0.0;
  Eigen::AlignedBox3d all_foods_m;
  for (int i = 0; i < count; ++i) {
    const FoodConfig& food = config.foods[i];
    const std::string field = "scene.objects[" + std::to_string(i) + "]";
    const std::unique_ptr<mpm::FoodShape>& shape = shapes[i];
    solver_model.materials.push_back(ResolveFoodMaterial(food, field));
    const Eigen::Isometry3d pose = FoodPose(food, *shape, layout, i, count);
    if (!pose.translation().allFinite()) throw SceneError(field + ".pose.position must be finite");
    const Eigen::AlignedBox3d box_m = WorldBox(*shape, pose);
    CheckOnTable(box_m, layout, field);
    all_foods_m.extend(box_m);
    // Before sampling: convex foods fill at least half their box (a sphere 52 %), so half the box's
    // count is a lower bound on what sampling would make.
    estimated_particles += 0.5 * EstimatedParticles(shape->LocalBounds().sizes(), resolution.dx_m,
                                                    resolution.particles_per_cell);
    if (estimated_particles > kMaxFoodParticles) {
      throw SceneError(field + ": the foods would need about " + std::to_string(static_cast<long long>(estimated_particles)) +
                       " particles, more than the " + std::to_string(kMaxFoodParticles) +
                       " a session may hold; use a coarser scene.quality, fewer particles_per_cell or a smaller scale");
    }
    food_model.initial_grid_nodes = EstimatedGridNodes(all_foods_m, resolution.dx_m);
    if (food_model.initial_grid_nodes > kMaxInitialGridNodes) {
      throw SceneError(field + ": the foods spread over " + std::to_string(all_foods_m.sizes().maxCoeff()) +
                       " m, an MPM grid of " + std::to_string(static_cast<long long>(food_model.initial_grid_nodes)) +
                       " nodes (limit " + std::to_string(static_cast<long long>(kMaxInitialGridNodes)) +
                       "); place the foods closer together or use a coarser scene.quality");
    }
    const std::size_t added = mpm::SampleFood(*shape, pose, solver.mass_scaling * solver_model.materials.back().density_kg_m3,
                                              static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(i), sampling,
                                              &food_model.initial_particles);
    if (added == 0) {
      throw SceneError(field + ": no particle fits in the " + food.food + " at dx = " + std::to_string(resolution.dx_m) +
                       " m; use a finer scene.quality or a larger scale");
    }
    if (food_model.initial_particles.size() > kMaxFoodParticles) {
      throw SceneError(field + ": the foods need more than " + std::to_string(kMaxFoodParticles) +
                       " particles; use a coarser scene.quality, fewer particles_per_cell or a smaller scale");
    }
    task::ObjectBox box;
    box.name = food.food + "_" + std::to_string(i);
    box.food = food.food;
    box.pose = pose;
    box.extent_m = shape->LocalBounds().sizes();
    food_model.objects.push_back(box);
  }
  // A second thread pays off only with enough particles to split; below that the OpenMP barriers of
  // a substep cost more than they save (idle machine: the 1.8k-particle draft cucumber spends 4.5 s
  // in MPM on 1 thread and 5.4 s on 2; at 10k particles 2 threads are 1.5x faster than 1,
  // docs/benchmarks/mpm_throughput.md).
  const std::size_t threads_by_size = food_model.initial_particles.size() / kParticlesPerMpmThread;
  solver.threads = static_cast<int>(std::clamp<std::size_t>(
      threads_by_size, 1, std::max(1u, std::min(2u, std::thread::hardware_concurrency()))));
  food_model.solver = std::make_shared<const mpm::SolverModel>(std::move(solver_model));
  return food_model;
}

}  // namespace culinarycut
