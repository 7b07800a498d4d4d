// Shared fixtures of the renderer tests: one renderer for the whole suite (starting EGL and
// compiling shaders takes a while), particle blocks standing in for food, robot link poses.
#pragma once

#include <memory>
#include <vector>

#include "sim/core/assets.h"
#include "sim/render/renderer.h"
#include "sim/robot/kinematics.h"
#include "sim/robot/robot_description.h"

namespace culinarycut::render::testing {

// The shipped Panda with knife, as the robot description reads it.
inline const RobotVisualDescription& PandaVisuals() {
  static const RobotDescription robot = LoadRobotDescription(AssetsDir() + "/panda/panda_knife.urdf", "knife_tcp");
  return robot.visuals;
}

inline Renderer& SharedRenderer() {
  static const std::unique_ptr<Renderer> renderer = [] {
    RendererOptions options;
    options.robot = PandaVisuals();
    return Renderer::Create(options);
  }();
  return *renderer;
}

// A food stand-in: particles 2.5 mm apart.
struct ParticleBlock : ParticleArrays {
  ParticleBlock() { spacing_m = 0.0025f; }

};

// A box of particles centred at `center_m`; with `gap_m` > 0 the slab |x - cx| < gap/2 is removed
// and the two halves become pieces 0 and 1, their cut faces damaged (flesh).
inline ParticleBlock MakeParticleBlock(const Eigen::Vector3d& center_m, const Eigen::Vector3d& size_m,
                                       double gap_m = 0.0, std::uint16_t object = 0) {
  ParticleBlock block;
  const double h = block.spacing_m;
  const Eigen::Vector3i n = (size_m / h).array().round().cast<int>();
  for (int i = 0; i < n.x(); ++i) {
    for (int j = 0; j < n.y(); ++j) {
      for (int k = 0; k < n.z(); ++k) {
        const Eigen::Vector3d p = center_m - 0.5 * size_m + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        const double along = p.x() - center_m.x();
        if (gap_m > 0.0 && std::abs(along) < 0.5 * gap_m) continue;
        block.x.push_back(static_cast<float>(p.x()));
        block.y.push_back(static_cast<float>(p.y()));
        block.z.push_back(static_cast<float>(p.z()));
        block.damage.push_back(gap_m > 0.0 && std::abs(along) < 0.5 * gap_m + 2.0 * h ? 1.0f : 0.0f);
        block.piece.push_back(gap_m > 0.0 && along > 0.0 ? 1 : 0);
        block.object.push_back(object);
      }
    }
  }
  return block;
}

// World poses of the Panda's base and movable links (base at the world origin) for joint angles q.
inline std::vector<Eigen::Isometry3d> PandaLinkPoses(const Eigen::VectorXd& q_rad) {
  static const RobotDescription robot = LoadRobotDescription(AssetsDir() + "/panda/panda_knife.urdf", "knife_tcp");
  std::vector<Eigen::Isometry3d> links;
  ForwardKinematics(robot, q_rad, &links);
  std::vector<Eigen::Isometry3d> poses = {Eigen::Isometry3d::Identity()};
  poses.insert(poses.end(), links.begin(), links.end());
  return poses;
}

// A pose with the knife above the board, blade down.
inline Eigen::VectorXd ReadyPose() {
  Eigen::VectorXd q(7);
  q << 0.0, 0.1, 0.0, -2.0, 0.0, 2.1, 0.785;
  return q;
}

}  // namespace culinarycut::render::testing
