#include "sim/world/camera_observation.h"

#include "sim/robot/kinematics.h"

namespace culinarycut {

render::RenderScene MakeRenderScene(const Model& model, const State& state) {
  render::RenderScene scene;
  scene.scene = model.config.scene;
  scene.layout = model.layout;
  // The renderer's pose order: [0] the base, [i + 1] the link moved by joint i.
  std::vector<Eigen::Isometry3d> links_in_base;
  ForwardKinematics(model.robot, state.physics->JointPositions(), &links_in_base);
  scene.link_poses_world.reserve(links_in_base.size() + 1);
  scene.link_poses_world.push_back(model.robot_base_in_world);
  for (const Eigen::Isometry3d& link : links_in_base) scene.link_poses_world.push_back(model.robot_base_in_world * link);

  if (model.food && state.food && state.food->solver) {
    const mpm::Particles<float>& particles = state.food->solver->particles();
    render::ParticleView& food = scene.food;
    food.count = particles.size();
    food.x_m = particles.position[0].data();
    food.y_m = particles.position[1].data();
    food.z_m = particles.position[2].data();
    food.damage = particles.damage.data();
    food.piece = particles.piece.data();
    food.object = particles.object.data();
    food.particle_spacing_m = static_cast<float>(model.food->particle_spacing_m);
    for (const task::ObjectBox& object : model.food->objects) scene.food_names.push_back(object.food);
  }
  return scene;
}

}  // namespace culinarycut
