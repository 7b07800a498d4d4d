// Everything that changes from frame to frame and that the cameras should see.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/render/particle_view.h"
#include "sim/core/scene_layout.h"

namespace culinarycut::render {

struct RenderScene {
  std::string scene = "table";  // "table" or "kitchen"
  SceneLayout layout;
  // World poses of the robot's base and movable link frames: [0] = base, [i + 1] = links[i] of
  // RobotDescription (forward kinematics in the base frame, pre-multiplied by the base pose).
  // Empty: no robot is drawn (and no camera may be attached to a link).
  std::vector<Eigen::Isometry3d> link_poses_world;
  ParticleView food;                    // read-only, valid during the Render call
  std::vector<std::string> food_names;  // per food object index, e.g. "cucumber"
};

}  // namespace culinarycut::render
