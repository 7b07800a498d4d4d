#include "sim/mpm/cut_record.h"

#include <Eigen/Eigenvalues>

namespace culinarycut::mpm {

void BladeNormalMoment::Add(const Eigen::Vector3d& blade_normal, double dt_s) {
  const Eigen::Vector3d n = blade_normal.normalized();
  normal_outer_s += dt_s * n * n.transpose();
  duration_s += dt_s;
}

std::optional<Eigen::Vector3d> BladeNormalMoment::MeanNormal() const {
  if (!(duration_s > 0.0)) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(normal_outer_s / duration_s);
  return eigen.eigenvectors().col(2).normalized();  // eigenvalues ascend: the largest is last
}

}  // namespace culinarycut::mpm
