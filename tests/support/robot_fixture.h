// The shipped Panda-with-knife description and a compiled default Model, loaded once per test binary.
#pragma once

#include <memory>
#include <random>

#include <Eigen/Core>

#include "sim/robot/robot_description.h"
#include "sim/world/model.h"

namespace culinarycut::testing {

inline const RobotDescription& Panda() {
  static const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  return robot;
}

inline std::shared_ptr<const Model> DefaultModel(const SceneConfig& config = {}) { return CompileModel(config, Panda()); }

// Joint angles drawn uniformly inside the limits, shrunk by `margin_rad` on each side.
inline Eigen::VectorXd RandomJointPositions(std::mt19937_64* rng, double margin_rad = 0.0) {
  Eigen::VectorXd q(Panda().dof());
  for (int i = 0; i < q.size(); ++i) {
    std::uniform_real_distribution<double> uniform(Panda().limits[i].lower_rad + margin_rad,
                                                   Panda().limits[i].upper_rad - margin_rad);
    q[i] = uniform(*rng);
  }
  return q;
}

}  // namespace culinarycut::testing
