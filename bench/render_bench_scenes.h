// Scenes shared by the render benchmark and the frame writer: a cucumber of about N particles
// sampled by the MPM food sampler, whole or cut in two (a gap with damaged, flesh-coloured faces),
// and the Panda holding the knife edge-down across it (inverse kinematics on the knife TCP).
#pragma once

#include <cmath>
#include <vector>

#include "sim/core/assets.h"
#include "sim/mpm/food_shapes.h"
#include "sim/render/camera.h"
#include "sim/render/particle_view.h"
#include "sim/render/renderer.h"
#include "sim/robot/inverse_kinematics.h"
#include "sim/robot/kinematics.h"
#include "sim/robot/robot_description.h"

namespace culinarycut::render::bench {

// Renderer options that draw the shipped Panda with knife, as the robot description reads it.
inline RendererOptions PandaRendererOptions() {
  RendererOptions options;
  options.robot = LoadRobotDescription(AssetsDir() + "/panda/panda_knife.urdf", "knife_tcp").visuals;
  return options;
}


struct FoodParticles : ParticleArrays {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  double top_z_m = 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // the cucumber's long axis (world)

};

// About `target_count` particles of a cucumber lying across the board centre, along world x.
// `cut`: the halves x < centre and x > centre are pieces 0 and 1, pushed half_gap_m apart each, and the
// particles within two spacings of the cut plane are fully damaged.
inline FoodParticles SampleCucumber(std::size_t target_count, const SceneLayout& layout, bool cut,
                                    double half_gap_m = 0.004) {
  const auto shape = mpm::MakeFoodShape("cucumber");
  const Eigen::AlignedBox3d bounds = shape->LocalBounds();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const double board_top = layout.board_center_m.z() + 0.5 * layout.board_size_m.z();
  pose.translation() = Eigen::Vector3d(layout.board_center_m.x(), layout.board_center_m.y(),
                                       board_top - bounds.min().z() + 0.001);
  pose.linear() = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ()).toRotationMatrix();  // a little askew
  mpm::SamplingOptions options;
  mpm::Particles<float> particles;
  // Two passes: the second scales dx so the count lands near the target.
  for (int pass = 0; pass < 2; ++pass) {
    particles = mpm::Particles<float>();
    mpm::SampleFood(*shape, pose, 1000.0, 0, 0, options, &particles);
    options.dx_m *= std::cbrt(static_cast<double>(particles.size()) / static_cast<double>(target_count));
  }
  FoodParticles food;
  food.axis = pose.linear().col(0);
  food.spacing_m = static_cast<float>(options.dx_m / std::cbrt(options.particles_per_cell));
  food.center_m = pose.translation();
  food.top_z_m = pose.translation().z() + bounds.max().z();
  const Eigen::Vector3d along = pose.linear().col(0);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    Eigen::Vector3d x(particles.position[0][p], particles.position[1][p], particles.position[2][p]);
    const double signed_distance = (x - food.center_m).dot(along);
    const bool right = signed_distance > 0.0;
    float damage = 0.0f;
    if (cut) {
      if (std::abs(signed_distance) < 2.0 * food.spacing_m) damage = 1.0f;
      x += (right ? half_gap_m : -half_gap_m) * along;
    }
    food.x.push_back(static_cast<float>(x.x()));
    food.y.push_back(static_cast<float>(x.y()));
    food.z.push_back(static_cast<float>(x.z()));
    food.damage.push_back(damage);
    food.piece.push_back(cut && right ? 1 : 0);
    food.object.push_back(0);
  }
  return food;
}

// World poses [base, links...] with the knife's cutting edge centre at `edge_m`, blade vertical and
// across the cucumber (whose axis is rotated `yaw_rad` about z).
inline std::vector<Eigen::Isometry3d> KnifeAt(const Eigen::Vector3d& edge_m, double yaw_rad) {
  static const RobotDescription robot = LoadRobotDescription(AssetsDir() + "/panda/panda_knife.urdf", "knife_tcp");
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d blade = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d down(0, 0, -1);
  target.linear().col(0) = blade;
  target.linear().col(1) = down.cross(blade);
  target.linear().col(2) = down;
  target.translation() = edge_m;
  Eigen::VectorXd seed(7);
  seed << 0.0, 0.1, 0.0, -2.0, 0.0, 2.1, 0.785;
  IkOptions options;
  options.max_iterations = 300;
  const IkResult ik = SolveInverseKinematics(robot, robot.TipFrame("knife_tcp"), target, seed, options);
  std::vector<Eigen::Isometry3d> links;
  ForwardKinematics(robot, ik.q_rad, &links);
  std::vector<Eigen::Isometry3d> poses = {Eigen::Isometry3d::Identity()};
  poses.insert(poses.end(), links.begin(), links.end());
  return poses;
}

}  // namespace culinarycut::render::bench
