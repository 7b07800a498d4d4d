// Where the static furniture stands: a plain type shared by the world (physics, food placement) and the
// renderer (furniture meshes, default cameras). World frame: z up, origin on the table top under the
// robot base.
#pragma once

#include <Eigen/Core>

namespace culinarycut {

struct SceneLayout {
  Eigen::Vector3d robot_base_position_m{0.0, 0.0, 0.0};
  Eigen::Vector3d table_size_m{1.2, 1.6, 0.05};        // top face at z = 0
  Eigen::Vector3d table_center_m{0.35, 0.0, -0.025};
  Eigen::Vector3d board_size_m{0.40, 0.30, 0.02};      // cutting board lying on the table
  Eigen::Vector3d board_center_m{0.50, 0.0, 0.01};     // top face at z = 0.02
  Eigen::Vector3d gravity_m_s2{0.0, 0.0, -9.81};
};

}  // namespace culinarycut
